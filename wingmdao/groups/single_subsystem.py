"""The linear solver of a group that holds one subsystem (the ``cases`` group of a one-case sizing)."""

from __future__ import annotations

import openmdao.api as om
from openmdao.core.constants import _UNDEFINED


class SingleSubsystemRunOnce(om.LinearRunOnce):
    """``LinearRunOnce`` without its copy of the group's derivative vector, in reverse mode, for a
    group whose one relevant subsystem receives no transfer inside the group.

    The block Gauss-Seidel sweep of ``LinearRunOnce`` first copies the group's whole derivative
    vector (the right-hand side) and, for each subsystem in turn, zeroes the subsystem's part,
    adds the transfers from its siblings and restores the right-hand side from the copy. With one
    subsystem and no transfer into it inside the group, that sweep leaves the vector as it was and
    then calls the subsystem's solve, so the copy (for the ``cases`` group of a gust sizing, every
    per-step output of the case: 20 MB for 20 nodes x 4001 steps) is not needed. In every other
    situation (forward mode, several subsystems, a transfer, MPI) this is ``LinearRunOnce``.
    """

    SOLVER = "LN: RUNONCE1"

    def _sole_subsystem(self, mode):
        """The group's one relevant local subsystem when the copy-free solve applies, else None."""
        system = self._system()
        if mode != "rev" or system.comm.size > 1:
            return None
        subs = list(system._relevance.filter(system._all_subsystem_iter()))
        if len(subs) != 1 or not subs[0]._is_local or subs[0].name in system._transfers["rev"]:
            return None
        return subs[0]

    def solve(self, mode, rel_systems=None):
        """Run the subsystem's solve (reverse mode, one subsystem), else ``LinearRunOnce.solve``."""
        subsys = self._sole_subsystem(mode)
        if subsys is None:
            return super().solve(mode, rel_systems)
        self._mode = mode
        system = self._system()
        scope_out, scope_in = system._get_matvec_scope(subsys)
        scope_out = self._union_matvec_scope(self._scope_out, scope_out)
        scope_in = self._union_matvec_scope(self._scope_in, scope_in)
        subsys._solve_linear(mode, scope_out, scope_in)
        if subsys._iter_call_apply_linear():
            subsys._apply_linear(mode, scope_out, scope_in)
        else:
            subsys._doutputs.set_val(0.0)
        self._scope_in = self._scope_out = _UNDEFINED
