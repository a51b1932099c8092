"""Python API (issue 11): wrong inputs are ValueErrors naming the argument, at setup, before any solve;
cases are built from plain keyword options (build_case), strings read as the command line would."""

import dataclasses

import numpy as np
import pytest

from wingmdao.cases import build_case, case_arguments, pegasus, wing_box
from wingmdao.sizing import build_problem


@pytest.fixture(scope="module")
def setup():
    return build_case("cantilever", stations=5)


def _build(setup, **change):
    kw = dict(geometry=setup.geometry, load_cases=setup.load_cases, material=setup.material,
              options=setup.options)
    kw.update(change)
    return build_problem(kw["geometry"], kw["load_cases"], kw["material"], kw["options"], driver=False)


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


def test_string_numbers_are_read_or_named():
    assert case_arguments(pegasus, load_factor="3.5").load_factor == 3.5
    with pytest.raises(ValueError, match="option load_factor = 'abc': not a valid float"):
        case_arguments(pegasus, load_factor="abc")
    with pytest.raises(ValueError, match=r"option loads = 'gusts'; allowed: maneuver, gust, all"):
        case_arguments(pegasus, loads="gusts")


def test_unknown_study():
    with pytest.raises(ValueError, match="option study = 7; allowed: 1, 2, 3"):
        case_arguments(wing_box, study=7)


def test_build_case_from_keywords_matches_the_command_line_path():
    from wingmdao.cli import build_parser

    a = build_case("pegasus", loads="maneuver", load_factor=2.0)
    b = pegasus.build(build_parser().parse_args(["size", "pegasus", "--load-factor", "2.0"]))
    np.testing.assert_array_equal(a.load_cases[0].forcing["force_per_length"],
                                  b.load_cases[0].forcing["force_per_length"])
