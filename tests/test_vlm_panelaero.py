"""wingmdao.aero.vlm against PanelAero's vortex lattice (DLR, BSD-3; the optional extra ``aero3d``).

PanelAero (A. Voss, https://github.com/DLR-AE/PanelAero, ``panelaero.VLM.calc_Qjj``) is an
independent implementation of the horseshoe lattice (Katz & Plotkin Ch. 10 / 12; Prandtl-Glauert
by Hedman's stretching). Given our panels' corners, control points and normals, both half wings
explicitly (its ``xz_symmetry`` option is not used), its pressure jumps times the panel areas are
the panels' normal forces per dynamic pressure, which must equal ours. Skipped when PanelAero is
not installed.
"""

import numpy as np
import pytest

from wingmdao.aero.vlm import build_lattice, solve_circulation

panelaero_vlm = pytest.importorskip("panelaero.VLM")


def _aerogrid(lat):
    """PanelAero's aerogrid of both halves (right: ours; left: the mirror image, P1 inboard ... the
    lower y first, so P1 -> P3 runs along +y on both halves as in PanelAero's sketch)."""
    m = np.array([1.0, -1.0, 1.0])
    area = lat.panel_chord * lat.span
    left_n = lat.normal * m
    return {"offset_j": np.vstack([lat.control, lat.control * m]),
            "offset_P1": np.vstack([lat.bound_a, lat.bound_b * m]),
            "offset_P3": np.vstack([lat.bound_b, lat.bound_a * m]),
            "N": np.vstack([lat.normal, left_n]),
            "A": np.concatenate([area, area]), "l": np.concatenate([lat.panel_chord, lat.panel_chord]),
            "n": 2 * lat.span.size}


@pytest.mark.parametrize("mach, dihedral_deg", [(0.0, 0.0), (0.6, 0.0), (0.4, 5.0)])
def test_panel_forces_equal_panelaero(mach, dihedral_deg):
    n, s = 9, 8.0
    y = s * np.sin(0.5 * np.pi * np.arange(n) / (n - 1))
    chord = 2.5 - 0.15 * y
    x_le = y * np.tan(np.radians(25.0))
    z = y * np.tan(np.radians(dihedral_deg))
    r = np.stack([x_le + 0.4 * chord, y, z], axis=-1)
    lat = build_lattice(r, chord, 0.4, mach=mach, n_chordwise=3, n_spanwise=2)
    alpha = 0.01 * (1.0 + 0.5 * lat.hat @ np.linspace(0, 1, n))  # a twisted wing, rad
    ours = 2.0 * solve_circulation(lat, alpha) * lat.span  # normal force per q (m^2)
    Qjj, _ = panelaero_vlm.calc_Qjj(_aerogrid(lat), mach)
    cp = Qjj @ np.concatenate([alpha, alpha])  # PanelAero's downwash w_j / V: + for a nose-up incidence
    theirs = cp[:lat.span.size] * lat.panel_chord * lat.span
    np.testing.assert_allclose(ours, theirs, rtol=1e-6, atol=1e-9 * np.max(np.abs(ours)))
