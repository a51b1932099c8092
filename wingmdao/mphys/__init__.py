"""MPhys builders of wingmdao (needs ``mphys``: ``pip install wingmdao[mdo]``).

``WingmdaoBuilder``: the static nonlinear box beam as an MPhys structural solver (6 dof per node).
``BeamRigidLinkBuilder``: rigid-link load and displacement transfer carrying moments and rotations.
``StickBuilder``: the stick model of the whole free aircraft (inertia relief) with the wing's interface.
See docs/embedding.md.
"""

try:
    import mphys  # noqa: F401
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise ImportError("wingmdao.mphys needs MPhys: pip install 'wingmdao[mdo]' (mphys>=2)") from exc

from wingmdao.mphys.builder import BeamRigidLinkBuilder, WingmdaoBuilder  # noqa: E402
from wingmdao.mphys.stick import StickBuilder, pegasus_stick_builder  # noqa: E402

__all__ = ["WingmdaoBuilder", "BeamRigidLinkBuilder", "StickBuilder", "pegasus_stick_builder"]
