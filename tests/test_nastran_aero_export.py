"""``wingmdao export pegasus --format nastran-aeroelastic`` (wingmdao.fe.nastran_aero): the deck is
read back by a small fixed-field reader written here (not the writer's) and checked against the
beam model it came from: total mass and centre of gravity against the beam's mass integration, the
PBEAM/MAT1 stiffness against the box sections, the CAERO1 panels against the planform area, the
splines against the grids and boxes, the TABRND1 spectrum against the von Karman PSD written out
here, and every card against the small-field format rules."""

import re

import numpy as np
import pytest
from scipy.integrate import quad

from wingmdao.beam.geometry import polyline_beam
from wingmdao.beam.rotations import body_to_csn
from wingmdao.beam.static import beam_parameters
from wingmdao.cases import pegasus as case
from wingmdao.cases.pegasus_verification import default_walls, nastran_aeroelastic_deck, pegasus_setup
from wingmdao.cli import main
from wingmdao.fe.nastran_aero import FlightData, LiftingPanel, aeroelastic_deck, nastran_real
from wingmdao.materials import ALUMINIUM
from wingmdao.section.box import box_properties

FT = 0.3048
INT = re.compile(r"^[+-]?\d+$")
REAL = re.compile(r"^[+-]?(\d+\.\d*|\.\d+)([eEdD]?[+-]?\d+)?$")
NAME = re.compile(r"^[A-Z][A-Z0-9()]*$")


def num(text):
    s = text.strip()
    sign = -1.0 if s.startswith("-") else 1.0
    s = s.lstrip("+-")
    m = REAL.match(s)
    assert m, f"not a Nastran real: {text!r}"
    exponent = (m.group(2) or "").lstrip("eEdD")
    return sign * float(m.group(1)) * 10.0 ** int(exponent or 0)


def read_fixed_bulk(text):
    """{card: [[field strings]]} of the bulk data, checking the small-field rules on the way: lines
    of at most 80 characters, a continued line with '+' in field 10 followed by a line with '+' in
    field 1, every field blank, an integer, a real with a decimal point, or a name."""
    lines = text.splitlines()
    start = lines.index("BEGIN BULK") + 1
    assert lines[-1] == "ENDDATA"
    cards, continued, current = {}, False, None
    for line in lines[start:-1]:
        assert len(line) <= 80, line
        if line.startswith("$"):
            continue
        padded = f"{line:<80}"
        fields = [padded[k:k + 8].strip() for k in range(0, 80, 8)]
        if continued:
            assert fields[0] == "+", f"continuation expected: {line!r}"
            cards[current][-1] += fields[1:9]
        else:
            assert NAME.match(fields[0]), f"card name expected: {line!r}"
            current = fields[0]
            cards.setdefault(current, []).append(fields[1:9])
        assert fields[9] in ("", "+"), line
        continued = fields[9] == "+"
        for f in fields[1:9]:
            assert f == "" or INT.match(f) or REAL.match(f.lstrip("+-")) or NAME.match(f), (f, line)
    assert not continued
    return {k: [_trim(c) for c in v] for k, v in cards.items()}


def _trim(fields):
    while fields and fields[-1] == "":
        fields = fields[:-1]
    return fields


@pytest.fixture(scope="module")
def model():
    walls = default_walls(20)
    geo, _, _, params, structural, _ = pegasus_setup(walls, 1.0)
    return {"walls": walls, "geo": geo, "params": params, "structural": structural,
            "cards": read_fixed_bulk(nastran_aeroelastic_deck(walls, sol=146))}


@pytest.mark.parametrize("x", [0.0, 1.0, -1.0, 0.5, -0.5, 1 / 3, -2 / 3, 1e-5, -1.23456789e-5, 1.23456789e-10,
                               123456789.0, -123456789.0, 99999999.0, 1e100, -1e-300, 5e-324, 70e9, 2.6315789e10,
                               -0.0299, 12345.678, 1e-99, -9.87654e-100])
def test_real_fits_eight_characters(x):
    """Every real in at most 8 characters, with a decimal point, read back by the test's own rule
    within the digits 8 characters can hold: at least 4 significant digits (relative 5e-4; a
    negative value with an exponent: sign, point and '-5' leave 4) while the exponent has one or two
    digits, at least 1 (5e-1 relative) at three-digit exponents."""
    text = nastran_real(x)
    assert len(text) <= 8 and "." in text and REAL.match(text.lstrip("+-")), text
    digits = 1 if x != 0 and (abs(x) < 1e-99 or abs(x) >= 1e100) else 4
    assert num(text) == pytest.approx(x, rel=0.5 * 10.0 ** (1 - digits), abs=1e-320)


def test_real_refuses_non_finite():
    for bad in (float("nan"), float("inf"), -float("inf")):
        with pytest.raises(ValueError, match="finite"):
            nastran_real(bad)


def test_total_mass_and_cg_equal_the_beams(model):
    """CONM2 masses against the beam's mass integration: total = sum over elements of
    ds (mu_a + mu_b) / 2 (= the boxes' rho A integrated plus the 600 + 150 kg engines), centre of
    gravity = sum of m_e (mid-point + the mass-centre offset in the element's jig axes) / total."""
    p, cards = model["params"], model["cards"]
    r, mu, cg, th = (np.asarray(p[k], float) for k in ("node_positions", "mass_per_length", "mass_center",
                                                       "node_euler_angles"))
    ds = np.linalg.norm(np.diff(r, axis=0), axis=1)
    m_e = ds * 0.5 * (mu[:-1] + mu[1:])
    arms = [body_to_csn(0.5 * (th[i] + th[i + 1])).T @ np.array([0.5 * (cg[i, 0] + cg[i + 1, 0]), 0.0,
                                                                 0.5 * (cg[i, 1] + cg[i + 1, 1])])
            for i in range(len(ds))]
    total = m_e.sum()
    centre = sum(m * (0.5 * (r[i] + r[i + 1]) + arms[i]) for i, m in enumerate(m_e)) / total
    structural = model["structural"]
    assert total == pytest.approx(np.sum(ds * 0.5 * (structural[:-1] + structural[1:])) + 750.0, rel=1e-12)

    grids = {int(c[0]): np.array([num(v) for v in c[2:5]]) for c in cards["GRID"]}
    mass = np.array([num(c[3]) for c in cards["CONM2"]])
    where = np.array([grids[int(c[1])] + [num(v) for v in c[4:7]] for c in cards["CONM2"]])
    assert all(int(c[2]) == 0 for c in cards["CONM2"])
    assert mass.sum() == pytest.approx(total, rel=2e-5)
    assert mass @ where / mass.sum() == pytest.approx(centre, abs=2e-5)
    assert np.allclose(np.array([grids[k + 1] for k in range(len(r))]), r, atol=1e-5)


def test_beam_stiffness_equals_the_sections(model):
    """PBEAM x MAT1 of every element against the box sections of its two stations (E Ixx, E Izz,
    G J, E A of box_properties, combined as the beam element combines them: the mean of the
    compliances)."""
    cards, geo, walls = model["cards"], model["geo"], model["walls"]
    E, G = (num(v) for v in cards["MAT1"][0][1:3])
    assert E == pytest.approx(ALUMINIUM.E) and G == pytest.approx(ALUMINIUM.G, rel=5e-4)  # 4 digits in 8 characters
    sec = [box_properties(geo.width[k], geo.height[k], *(walls[w][k] for w in
                          ("t_upper_skin", "t_lower_skin", "t_front_spar", "t_rear_spar")), ALUMINIUM)
           for k in range(geo.num_nodes)]
    harmonic = lambda key, i: 2.0 / (1.0 / sec[i][key] + 1.0 / sec[i + 1][key])   # noqa: E731
    pbeam = {int(c[0]): c for c in cards["PBEAM"]}
    assert len(cards["CBEAM"]) == geo.num_nodes - 1
    for cb in cards["CBEAM"]:
        i = int(cb[2]) - 1
        assert int(cb[3]) == i + 2
        pb = pbeam[int(cb[1])]
        area, i1, i2, i12, j = (num(v) for v in pb[2:7])
        assert E * i1 == pytest.approx(harmonic("EIxx", i), rel=1e-4)
        assert E * i2 == pytest.approx(harmonic("EIzz", i), rel=1e-4)
        assert G * j == pytest.approx(harmonic("GJ", i), rel=1e-4)
        assert E * area == pytest.approx(harmonic("EA", i), rel=1e-4)
        assert abs(i12) <= 1e-9 * i1      # equal skins: no product of inertia
        # end B ('YESA', x/xb = 1) repeats end A: a prismatic element
        assert pb[16] == "YESA" and num(pb[17]) == 1.0 and pb[18:23] == pb[2:7]
        # orientation vector: the element's n axis, here body z
        assert np.allclose([num(v) for v in cb[4:7]], [0, 0, 1], atol=1e-6)


def test_stiffness_tensor_and_offsets_of_a_coupled_swept_beam():
    """A swept, dihedral beam with an I12 coupling and offset axes: E (I1 z z^T + I2 y y^T - I12
    (y z^T + z y^T)) of the deck's element axes (x = GA -> GB, y in the plane of x and the
    orientation vector) equals the beam's T^T E_csn T, and the CBEAM offset is its shear centre."""
    pts = np.array([[0.0, 0.0, 0.0], [1.0, 4.0, 0.5]])
    geo = polyline_beam(pts, [3])
    ei_cc, ei_nn, ei_cn, gj = 2.0e7, 9.0e7, 0.6e7, 1.5e7
    p = beam_parameters(geo.node_positions, geo.node_euler_angles, EI_cc=ei_cc, GJ=gj, EI_nn=ei_nn, EA=3.0e9,
                        EI_cn=ei_cn, GK_c=1e9, GK_n=2e9, tension_axis=(0.05, -0.02), shear_center=(-0.1, 0.03),
                        mass_per_length=12.0, mass_center=(0.2, 0.01))
    panel = LiftingPanel((-0.5, 0.0, 0.0), 2.0, (0.5, 4.0, 0.5), 1.0, 4, 2, (0, 1, 2, 3))
    flight = FlightData(1.5, 8.0, 6.0, 0.5, 150.0, 0.5, 0.6, 0.5, (100.0, 120.0), 0.5, 5000.0)
    cards = read_fixed_bulk(aeroelastic_deck(p, ALUMINIUM, [panel], flight, sol=145, modes=6))
    E, G = (num(v) for v in cards["MAT1"][0][1:3])
    grids = {int(c[0]): np.array([num(v) for v in c[2:5]]) for c in cards["GRID"]}
    pbeam = {int(c[0]): c for c in cards["PBEAM"]}
    for cb in cards["CBEAM"]:
        i = int(cb[2]) - 1
        x = grids[int(cb[3])] - grids[int(cb[2])]
        x /= np.linalg.norm(x)
        v = np.array([num(s) for s in cb[4:7]])
        y = v - (v @ x) * x
        y /= np.linalg.norm(y)
        z = np.cross(x, y)
        _, _, area, i1, i2, i12, j = (num(s) if k > 1 else s for k, s in enumerate(pbeam[int(cb[1])][:7]))
        deck = E * (i1 * np.outer(z, z) + i2 * np.outer(y, y) - i12 * (np.outer(y, z) + np.outer(z, y)))
        T = body_to_csn(0.5 * (geo.node_euler_angles[i] + geo.node_euler_angles[i + 1]))
        bending = T.T @ np.array([[ei_cc, 0, ei_cn], [0, 0, 0], [ei_cn, 0, ei_nn]]) @ T
        assert np.allclose(deck, bending, rtol=0, atol=2e-4 * ei_nn)
        assert G * j == pytest.approx(gj, rel=1e-4) and E * area == pytest.approx(3.0e9, rel=1e-4)
        offsets = [num(s) for s in cb[10:16]]
        assert np.allclose(offsets[:3], T.T @ [-0.1, 0.0, 0.03], atol=2e-5) and offsets[:3] == offsets[3:]
        # neutral axis from the shear centre in element (y, z) = (n, c)
        n1, n2 = (num(s) for s in pbeam[int(cb[1])][36:38])
        assert (n1, n2) == pytest.approx((-0.02 - 0.03, 0.05 + 0.1), abs=1e-6)


def test_panels_cover_the_planform(model):
    """The CAERO1 trapezoids (points 1 and 4 and their chords) add up to the half planform,
    586.33 ft^2 / 2, and reach from the symmetry plane to the semi-span."""
    cards = model["cards"]
    area, spans = 0.0, []
    for c in cards["CAERO1"]:
        x1, y1, z1, c12, x4, y4, z4, c43 = (num(v) for v in c[8:16])
        area += 0.5 * (c12 + c43) * (y4 - y1)
        spans.append((y1, y4))
    assert area == pytest.approx(case.PLANFORM.area_ft2 * FT**2 / 2, rel=1e-5)
    spans.sort()
    assert spans[0][0] == 0.0 and spans[-1][1] == pytest.approx(case.PLANFORM.semi_span, abs=1e-5)
    assert all(a[1] == b[0] for a, b in zip(spans, spans[1:]))
    aeros = cards["AEROS"][0]
    assert num(aeros[4]) == pytest.approx(case.PLANFORM.area_ft2 * FT**2 / 2, rel=1e-5)
    assert num(aeros[3]) == pytest.approx(case.PLANFORM.span_ft * FT, rel=1e-5)


def test_splines_reference_existing_grids_and_boxes(model):
    """Every SPLINE2 names a CAERO1, a box range inside it, a SET1 of existing grids and a CORD2R;
    the splines cover every box exactly once."""
    cards = model["cards"]
    grids = {int(c[0]) for c in cards["GRID"]}
    sets = {int(c[0]): [int(v) for v in c[1:]] for c in cards["SET1"]}
    cords = {int(c[0]) for c in cards["CORD2R"]}
    boxes = {}
    for c in cards["CAERO1"]:
        eid, nspan, nchord = int(c[0]), int(c[3]), int(c[4])
        boxes[eid] = set(range(eid, eid + nspan * nchord))
    every = set().union(*boxes.values())
    covered = []
    for s in cards["SPLINE2"]:
        caero, id1, id2, setg, cid = int(s[1]), int(s[2]), int(s[3]), int(s[4]), int(s[7])
        assert caero in boxes and {id1, id2} <= boxes[caero]
        assert setg in sets and set(sets[setg]) <= grids and len(sets[setg]) >= 2
        assert cid in cords
        assert [num(v) for v in s[8:10]] == [0.0, 0.0]     # slope and twist attached
        covered += list(range(id1, id2 + 1))
    assert sorted(covered) == sorted(every)
    assert not grids & every      # aerodynamic box ids clear of the structural grids


def test_gust_spectrum_is_von_karman(model):
    """TABRND1 against 25.341(b)(2)'s von Karman PSD written here in Hz (L = 2,500 ft, sigma = 1
    m/s, V of GUST): the values, and the table's log-log integral against the closed spectrum's
    integral over the same band (the full integral is sigma^2 = 1)."""
    cards = model["cards"]
    velocity = num(cards["GUST"][0][4])
    assert num(cards["GUST"][0][2]) == pytest.approx(1.0 / velocity, rel=1e-4)
    L = 2500 * FT

    def psd(f):
        x2 = (1.339 * L * 2 * np.pi * f / velocity) ** 2
        return 2 * L / velocity * (1 + 8 / 3 * x2) / (1 + x2) ** (11 / 6)

    # 1 - 1.1e-5: 1.339 is the rounded a = Gamma(1/3) / (sqrt(pi) Gamma(5/6)) = 1.33898
    assert quad(psd, 0, np.inf, limit=200)[0] == pytest.approx(1.0, rel=1e-4)
    tab = cards["TABRND1"][0]
    assert tab[1:3] == ["LOG", "LOG"] and tab[-1] == "ENDT"
    pairs = np.array([num(v) for v in tab[8:-1]]).reshape(-1, 2)
    f, g = pairs.T
    assert np.allclose(g, psd(f), rtol=1e-4)
    # log-log interpolation integrated segment by segment (power law g = g0 (f/f0)^b)
    b = np.diff(np.log(g)) / np.diff(np.log(f))
    seg = g[:-1] * f[:-1] / (b + 1) * ((f[1:] / f[:-1]) ** (b + 1) - 1)
    assert seg.sum() == pytest.approx(quad(psd, f[0], f[-1], limit=200)[0], rel=2e-3)


@pytest.mark.parametrize("sol, lines", [(144, ["TRIM = 70"]), (145, ["METHOD = 10", "FMETHOD = 30"]),
                                        (146, ["METHOD = 10", "FREQ = 40", "GUST = 50", "DLOAD = 51",
                                               "RANDOM = 60"])])
def test_case_control_of_each_solution(sol, lines):
    text = nastran_aeroelastic_deck(default_walls(20), sol=sol, spanwise_boxes=6, chordwise_boxes=2)
    control = text.split("BEGIN BULK")[0].splitlines()
    assert f"SOL {sol}" in control and "SPC = 1" in control
    assert all(f"  {line}" in control for line in lines)
    cards = read_fixed_bulk(text)
    referenced = {144: ("TRIM", 70), 145: ("FLUTTER", 30), 146: ("GUST", 50)}[sol]
    assert int(cards[referenced[0]][0][0]) == referenced[1]
    assert int(cards["EIGRL"][0][0]) == 10 and int(cards["SPC1"][0][2]) == 1


def test_cli_writes_the_deck_and_refuses_bad_input(tmp_path, capsys):
    path = tmp_path / "pegasus_aero.bdf"
    argv = ["export", "pegasus", "--format", "nastran-aeroelastic", "--sol", "145", "--spanwise-boxes", "6",
            "--chordwise-boxes", "2", str(path)]
    assert main(argv) == 0
    cards = read_fixed_bulk(path.read_text())
    assert sum(int(c[3]) for c in cards["CAERO1"]) == 6
    before = path.read_text()
    assert main(argv) != 0
    assert "exists" in capsys.readouterr().err and path.read_text() == before
    assert main(argv[:-1] + ["--overwrite", str(path)]) == 0
    capsys.readouterr()
    bad = [(["--fidelity", "shell"], "--fidelity shell"), (["--modes", "0"], "--modes = 0"),
           (["--spanwise-boxes", "1"], "--spanwise-boxes = 1"), (["--load-factor", "2.5"], "--load-factor")]
    for extra, message in bad:
        other = tmp_path / "x.bdf"
        assert main(["export", "pegasus", "--format", "nastran-aeroelastic", *extra, str(other)]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1 and not other.exists()
    assert main(["export", "pegasus", "--format", "nastran", "--sol", "146", str(tmp_path / "y.bdf")]) == 2
    assert "--sol is read by --format nastran-aeroelastic only" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["export", "pegasus", "--format", "nastran-aero", str(tmp_path / "z.bdf")])
    assert "invalid choice" in capsys.readouterr().err


def _beam_element_stiffness(E, G, area, i1, i2, j, k1, k2, length):
    """12 x 12 Timoshenko beam stiffness in element axes (u, v, w, rx, ry, rz at A then B): bending
    in plane 1 (x-y, about z) with I1 and shear area K1 A, in plane 2 (x-z, about y) with I2, K2 A
    (Przemieniecki, Theory of Matrix Structural Analysis, 1968, Sec. 5.6, with Phi = 12 E I / (G As L^2))."""
    k = np.zeros((12, 12))
    L = length
    for a, b, s in ((0, 6, E * area / L), (3, 9, G * j / L)):
        k[np.ix_([a, b], [a, b])] = s * np.array([[1, -1], [-1, 1]])
    for (v, r, ei, ks, sign) in ((1, 5, E * i1, k1, 1.0), (2, 4, E * i2, k2, -1.0)):
        phi = 12 * ei / (G * ks * area * L**2)
        idx = [v, r, v + 6, r + 6]
        c = ei / (L**3 * (1 + phi))
        kb = c * np.array([[12, 6 * L, -12, 6 * L], [6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2],
                           [-12, -6 * L, 12, -6 * L], [6 * L, (2 - phi) * L**2, -6 * L, (4 + phi) * L**2]])
        s = np.diag([1.0, sign, 1.0, sign])       # w with ry: dw/dx = -ry
        k[np.ix_(idx, idx)] = s @ kb @ s
    return k


def test_deck_natural_frequencies_equal_the_beams(model):
    """A 6-DOF-per-node Timoshenko frame FE assembled here from the parsed GRID, CBEAM, PBEAM
    (A, I1, I2, J, K1, K2), MAT1, CONM2 (rigid-body 6 x 6 masses with their offsets and inertia, the
    CONM2 sign convention [[I11, -I21, -I31], ...]) and SPC1, against the project's beam modes
    (wingmdao.beam.modes, the linearised residual): the first four natural frequencies (1.79, 5.35,
    8.23, 24.1 Hz on the beam) within 1.5 % (measured -0.2, -0.2, -1.1, -1.0 %). Left out of the
    frame FE: the shear-centre / neutral-axis offsets; of the lumped masses: each element's spanwise
    rotary inertia m ds^2 / 12. Without K1, K2 (shear-rigid elements) the fourth, chordwise bending
    of the 1.26-1.28 m wide box, is 7 % high: the shear factors carry the beam's shear flexibility."""
    from scipy.linalg import eigh

    from wingmdao.beam.modes import natural_frequencies
    from wingmdao.beam.residual import forcing_specs
    from wingmdao.beam.static import BeamModel, beam_forcing
    from wingmdao.timemarch.system import pack

    cards = model["cards"]
    E, G = (num(v) for v in cards["MAT1"][0][1:3])
    ids = [int(c[0]) for c in cards["GRID"]]
    pos = {int(c[0]): np.array([num(v) for v in c[2:5]]) for c in cards["GRID"]}
    dof = {g: 6 * k for k, g in enumerate(ids)}
    n = 6 * len(ids)
    K, M = np.zeros((n, n)), np.zeros((n, n))
    pbeam = {int(c[0]): c for c in cards["PBEAM"]}
    for cb in cards["CBEAM"]:
        ga, gb = int(cb[2]), int(cb[3])
        x = pos[gb] - pos[ga]
        L = np.linalg.norm(x)
        x /= L
        v = np.array([num(s) for s in cb[4:7]])
        y = v - (v @ x) * x
        y /= np.linalg.norm(y)
        R = np.array([x, y, np.cross(x, y)])
        area, i1, i2, _, j = (num(s) for s in pbeam[int(cb[1])][2:7])
        k1, k2 = (num(s) for s in pbeam[int(cb[1])][24:26])
        T = np.kron(np.eye(4), R)
        idx = [*range(dof[ga], dof[ga] + 6), *range(dof[gb], dof[gb] + 6)]
        K[np.ix_(idx, idx)] += T.T @ _beam_element_stiffness(E, G, area, i1, i2, j, k1, k2, L) @ T
    for c in cards["CONM2"]:
        m, d = num(c[3]), np.array([num(v) for v in c[4:7]])
        assert c[7] == ""         # field 9 blank: the inertia starts on the continuation
        i11, i21, i22, i31, i32, i33 = (num(v) for v in c[8:14])
        J = np.array([[i11, -i21, -i31], [-i21, i22, -i32], [-i31, -i32, i33]])
        D = np.array([[0, -d[2], d[1]], [d[2], 0, -d[0]], [-d[1], d[0], 0]])
        rigid = np.block([[m * np.eye(3), -m * D], [m * D, J + m * D.T @ D]])
        idx = range(dof[int(c[1])], dof[int(c[1])] + 6)
        M[np.ix_(idx, idx)] += rigid
    free = [k for k in range(n) if k // 6 != dof[int(cards["SPC1"][0][2])] // 6]
    w2 = eigh(K[np.ix_(free, free)], M[np.ix_(free, free)], eigvals_only=True, subset_by_index=[0, 3])
    deck = np.sqrt(w2) / (2 * np.pi)

    beam = BeamModel(model["params"])
    f = natural_frequencies(beam.system, beam.p, pack(forcing_specs(beam.num_nodes), beam_forcing(beam.num_nodes)),
                            count=4)
    assert deck == pytest.approx(f, rel=0.015)


def test_design_walls_reach_the_deck(tmp_path):
    """`--design RESULT.json`: the deck's stiffness and mass are those of the design's walls
    (tapered, unequal skins and spars: the product of inertia is not zero)."""
    import json

    walls = {"upper_skin": np.linspace(0.008, 0.002, 20), "lower_skin": np.linspace(0.007, 0.002, 20),
             "front_spar": np.full(20, 0.006), "rear_spar": np.full(20, 0.003)}
    design = tmp_path / "design.json"
    design.write_text(json.dumps({"case": "pegasus", "thickness": {k: v.tolist() for k, v in walls.items()}}))
    path = tmp_path / "d.bdf"
    assert main(["export", "pegasus", "--format", "nastran-aeroelastic", "--design", str(design), str(path)]) == 0
    cards = read_fixed_bulk(path.read_text())
    geo = pegasus_setup(default_walls(20), 1.0)[0]
    E = num(cards["MAT1"][0][1])
    for i in (0, 9, 18):
        sec = [box_properties(geo.width[k], geo.height[k], *(walls[w][k] for w in
                              ("upper_skin", "lower_skin", "front_spar", "rear_spar")), ALUMINIUM) for k in (i, i + 1)]
        pb = next(c for c in cards["PBEAM"] if int(c[0]) == i + 1)
        assert E * num(pb[3]) == pytest.approx(2 / (1 / sec[0]["EIxx"] + 1 / sec[1]["EIxx"]), rel=1e-4)
        # unequal skins and spars put the centroid off both box axes: I12 = int(n c) dA = Ixz, not zero
        assert num(pb[5]) == pytest.approx(0.5 * (sec[0]["Ixz"] + sec[1]["Ixz"]), rel=0.1)
    ds = np.linalg.norm(np.diff(geo.node_positions, axis=0), axis=1)
    rho_a = np.array([ALUMINIUM.rho * box_properties(geo.width[k], geo.height[k],
                                                     *(walls[w][k] for w in ("upper_skin", "lower_skin", "front_spar",
                                                                             "rear_spar")), ALUMINIUM)["A"]
                      for k in range(20)])
    mass = sum(num(c[3]) for c in cards["CONM2"])
    assert mass == pytest.approx(np.sum(ds * 0.5 * (rho_a[:-1] + rho_a[1:])) + 750.0, rel=2e-5)


def test_cards_loads_kernel_reads_have_fixed_line_counts(model):
    """Loads Kernel's reader takes GRID as one line, CORD2R and CAERO1 as two, and a SET1 as long
    as field 10 of a line equals field 1 of the next: the deck's lines satisfy exactly that."""
    text = nastran_aeroelastic_deck(default_walls(20), sol=146)
    lines = [line for line in text.split("BEGIN BULK\n")[1].splitlines() if not line.startswith("$")]
    expected = {"GRID": 1, "CORD2R": 2, "CAERO1": 2}
    for k, line in enumerate(lines):
        name = line[:8].strip()
        if name in expected:
            block = lines[k:k + expected[name] + 1]
            assert all(f"{b:<80}"[72:80].strip() == "+" for b in block[:expected[name] - 1])
            last = f"{block[expected[name] - 1]:<80}"[72:80].strip()
            assert last == "" and block[expected[name]][:8].strip() != last


def test_bending_torsion_coupled_section_is_refused():
    """PBEAM has no field for a bending-torsion coupling (E_cs): a one-line error, no deck."""
    p = beam_parameters(np.array([[0.0, 0, 0], [0, 1, 0], [0, 2, 0]]), np.zeros(3), EI_cc=1e6, GJ=1e6, EI_nn=1e7,
                        EA=1e9, mass_per_length=1.0)
    p["stiffness_csn"][:, 0, 1] = p["stiffness_csn"][:, 1, 0] = 2e5
    panel = LiftingPanel((-0.5, 0.0, 0.0), 1.0, (-0.5, 2.0, 0.0), 1.0, 2, 2, (0, 1, 2))
    flight = FlightData(1.0, 4.0, 2.0, 0.5, 150.0, 0.5, 0.6, 0.5, (100.0,), 0.5, 5000.0)
    with pytest.raises(ValueError, match="bending-torsion coupling"):
        aeroelastic_deck(p, ALUMINIUM, [panel], flight)
