"""Python API (issue 11): wrong inputs are ValueErrors naming the argument, at setup, before any solve;
cases are built from plain keyword options (build_case), strings read as the command line would."""

import dataclasses

import numpy as np
import pytest

from wingmdao.cases import build_case, options_from_namespace, pegasus, wing_box
from wingmdao.sizing import build_problem


@pytest.fixture(scope="module")
def setup():
    return build_case("cantilever", stations=5)


def _build(setup, **change):
    kw = dict(geometry=setup.geometry, load_cases=setup.load_cases, material=setup.material,
              options=setup.options)
    kw.update(change)
    return build_problem(kw["geometry"], kw["load_cases"], kw["material"], kw["options"], driver=False,
                         section=setup.section)


@pytest.mark.parametrize("change, message", [
    (dict(material="aluminium"), "material must be a wingmdao.materials.Material"),
    (dict(load_cases=[]), "load_cases is empty"),
    (dict(load_cases=[1.0]), "load_cases must hold LoadCase objects"),
])
def test_wrong_arguments_name_the_argument(setup, change, message):
    with pytest.raises(ValueError, match=message):
        _build(setup, **change)


def test_station_map_of_wrong_length(setup):
    geometry = dataclasses.replace(setup.geometry, station_map=np.array([0, 0, 1]))
    with pytest.raises(ValueError, match=r"geometry.station_map: shape \(3,\).*needs \(5,\)"):
        _build(setup, geometry=geometry)


def test_rho_ks_below_the_sane_minimum(setup):
    with pytest.raises(ValueError, match=r"options.rho_ks = 2.0; allowed range \[10, inf\)"):
        _build(setup, options=dataclasses.replace(setup.options, rho_ks=2.0))
    with pytest.raises(ValueError, match="options.rho_ks = '100'"):
        _build(setup, options=dataclasses.replace(setup.options, rho_ks="100"))


def test_unknown_case_and_option():
    with pytest.raises(ValueError, match="unknown case 'pegasys'"):
        build_case("pegasys")
    with pytest.raises(ValueError, match="pegasus has no option 'load_factr'"):
        build_case("pegasus", load_factr=2.5)


def test_string_numbers_and_wrong_types_are_named():
    """The keyword API takes numbers, not strings: a string is an error naming the option (no silent parse)."""
    with pytest.raises(ValueError, match=r"pegasus option load_factor = '3.5' \(str\): must be a number"):
        pegasus.PegasusOptions(load_factor="3.5")
    with pytest.raises(ValueError, match=r"pegasus option loads = 'gusts'; allowed: maneuver, gust, all"):
        pegasus.build(loads="gusts")
    with pytest.raises(ValueError, match=r"cantilever option stations = 5.5 \(float\): must be an integer"):
        build_case("cantilever", stations=5.5)
    with pytest.raises(ValueError, match=r"wing-box option elements = \(1, 'x', 1\): must be a list of integers"):
        wing_box.build(elements=(1, "x", 1))
    with pytest.raises(ValueError, match=r"pegasus option kussner = 1 \(int\): must be True or False"):
        pegasus.PegasusOptions(kussner=1)
    with pytest.raises(ValueError, match="crm option families = None: must be a string"):
        build_case("crm", families=None)


def test_options_object_of_another_type():
    with pytest.raises(ValueError, match="pegasus options must be a PegasusOptions"):
        pegasus.build(wing_box.WingBoxOptions())


def test_unknown_study():
    with pytest.raises(ValueError, match="wing-box option study = 7; allowed: 1, 2, 3"):
        wing_box.build(study=7)
    with pytest.raises(ValueError, match="wing-box option study = 7; allowed: 1, 2, 3"):
        build_case("wing-box", study=7)


def test_options_are_immutable_and_lists_become_tuples():
    import pathlib

    opts = pegasus.PegasusOptions(gust_gradients_ft=[30.0, 350.0], load_history=pathlib.Path("h.npz"))
    assert opts.gust_gradients_ft == (30.0, 350.0) and opts.load_history == "h.npz"
    with pytest.raises(dataclasses.FrozenInstanceError):
        opts.loads = "all"


def test_parser_defaults_are_the_dataclass_defaults():
    """One table of defaults: every case's command-line defaults come from its options dataclass."""
    import argparse

    from wingmdao.cases import add_option_arguments, available_cases

    for name, module in available_cases().items():
        parser = argparse.ArgumentParser()
        add_option_arguments(parser, module.OPTIONS)
        from_cli = options_from_namespace(module.OPTIONS, parser.parse_args([]))
        assert from_cli == module.OPTIONS(), name
        dests = set(vars(parser.parse_args([])))
        assert dests == {f.name for f in dataclasses.fields(module.OPTIONS)
                         if not f.metadata.get("shared")}, name  # shared flags: the command adds them


def test_build_case_from_keywords_matches_the_command_line_path():
    from wingmdao.cli import build_parser

    a = build_case("pegasus", loads="maneuver", load_factor=2.0)
    args = build_parser().parse_args(["size", "pegasus", "--load-factor", "2.0"])
    b = pegasus.build(options_from_namespace(pegasus.PegasusOptions, args))
    np.testing.assert_array_equal(a.load_cases[0].forcing["force_per_length"],
                                  b.load_cases[0].forcing["force_per_length"])


@pytest.mark.parametrize("change, message", [
    (lambda s: dict(geometry={"x": 1}), "geometry must be a wingmdao.sizing.WingGeometry, got dict"),
    (lambda s: dict(geometry=dataclasses.replace(s.geometry, node_positions=s.geometry.node_positions[:, :2])),
     r"geometry.node_positions: shape \(5, 2\); needs \(5, 3\)"),
    (lambda s: dict(geometry=dataclasses.replace(s.geometry, nonstructural_mass_per_length=np.ones(2))),
     r"geometry.nonstructural_mass_per_length: shape \(2,\); needs \(5,\)"),
    (lambda s: dict(options=dataclasses.replace(s.options, lower={})), "options.lower: no bound for width, height"),
    (lambda s: dict(options=dataclasses.replace(s.options, lower={"width": 6.0, "height": 0.4})),
     r"options.lower\['width'\] = 6.0 m, options.upper\['width'\] = 5.0 m; need 0 < lower <= upper"),
    (lambda s: dict(options=dataclasses.replace(s.options, initial={"width": np.ones(3)})),
     r"options.initial\['width'\]: 3 values; needs 1 or 5"),
    (lambda s: dict(options=dataclasses.replace(s.options, initial={"widht": 1.0})),
     r"options.initial\['widht'\]: not a design variable; allowed: width, height"),
    (lambda s: dict(options=dataclasses.replace(s.options, tol="1e-6")), r"options.tol = '1e-6'"),
    (lambda s: dict(options=dataclasses.replace(s.options, maxiter="200")), r"options.maxiter = '200'"),
    (lambda s: dict(options=dataclasses.replace(s.options, mass_scale=-1.0)), r"options.mass_scale = -1.0 kg"),
])
def test_geometry_and_options_errors_name_the_field(setup, change, message):
    """Shapes, bounds and types of the geometry and sizing options are checked before setup."""
    with pytest.raises(ValueError, match=message):
        _build(setup, **change(setup))


def test_every_shipped_case_passes_the_input_checks():
    from wingmdao.cases import available_cases
    from wingmdao.sizing import check_problem_inputs

    for name in available_cases():
        s = build_case(name)
        check_problem_inputs(s.geometry, s.load_cases, s.material, s.options, s.section)


@pytest.mark.parametrize("name, options", [("pegasus", {}), ("wing-box", {"elements": (2, 1, 2)}),
                                           ("cantilever", {"stations": 5})])
def test_design_beam_params_match_the_sizing_model(name, options, monkeypatch):
    """The beam parameters initial_frequencies uses come without a Problem and equal what the sizing
    model's section components feed its beam (station map, non-structural mass, sweep included)."""
    import openmdao.api as om

    from wingmdao.beam.residual import param_specs
    from wingmdao.groups.load_case import LoadCase
    from wingmdao.sizing import SECTION_KINDS, design_beam_params, initial_design

    s = build_case(name, **options)
    design = initial_design(s.options, SECTION_KINDS[s.section]["design_vars"])
    with monkeypatch.context() as m:
        m.setattr(om, "Problem", None)  # computed directly
        direct = design_beam_params(s.geometry, s.material, design, s.section)
    families = s.load_cases[0].families
    prob, _ = build_problem(s.geometry, [LoadCase("still", families=families)], s.material, s.options,
                            driver=False, section=s.section)
    prob.run_model()
    for spec in param_specs(s.geometry.num_nodes):
        model = np.asarray(prob.get_val(spec.name, units=spec.units)).reshape(spec.shape)
        np.testing.assert_allclose(direct[spec.name], model, rtol=1e-12, atol=1e-12 * np.abs(model).max(),
                                   err_msg=spec.name)


def test_one_family_vocabulary_for_every_case():
    """``--families`` reads the same names and shorthands on every sizing case (issue 11: one
    spelling per concept): family names, and ss / cent for both signs."""
    from wingmdao.cases import pegasus, wing_box
    from wingmdao.groups.load_case import parse_families

    assert parse_families("vm,ss") == ("vm", "ss_tension", "ss_compression")
    assert pegasus.parse_families("vm, cent") == ("vm", "cent_pos", "cent_neg")
    assert wing_box.parse_constraints("ss_tension,vm,ss") == ("ss_tension", "vm", "ss_compression")
    for parse in (pegasus.parse_families, wing_box.parse_constraints):
        with pytest.raises(ValueError, match=r"--families: unknown \['vn'\]; valid: vm, ss_tension"):
            parse("vm,vn")
