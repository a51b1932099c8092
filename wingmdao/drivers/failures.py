"""What the wingmdao drivers share about failed analyses (``om.AnalysisError`` of the model):
the one-line message and the recording of a failed evaluation with ``success = 0``."""

from __future__ import annotations


def one_line(exc) -> str:
    """The exception's text on one line.

    Parameters
    ----------
    exc : BaseException
        The exception.

    Returns
    -------
    str
        Its text with line breaks collapsed.
    """
    return " ".join(str(exc).split())


class RecordsFailedAnalyses:
    """Driver mixin: an evaluation whose analysis failed (``self._failure``, set by the driver's
    ``_run_solve_nonlinear``) is recorded with ``success = 0`` and the failure as its message, so
    ``wingmdao report`` and a restart never take it for a solution."""

    _failure = None

    def _get_recorder_metadata(self, case_name):
        meta = super()._get_recorder_metadata(case_name)
        if self._failure is not None:
            meta["success"] = 0
            meta["msg"] = f"analysis failed: {one_line(self._failure)}"
        return meta
