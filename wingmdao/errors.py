"""Exceptions shared by the components."""

from __future__ import annotations

import openmdao.api as om


class InputRangeError(om.AnalysisError, ValueError):
    """An input out of its allowed range found while a component computes.

    A ``ValueError`` (the message names the input, its value and the allowed range) and an
    ``om.AnalysisError``, so that a driver stepping outside the feasible box backs off instead of
    ending the run.
    """
