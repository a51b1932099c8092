"""A warning given at most once per process: a fallback taken many times is reported once."""

from __future__ import annotations

import warnings


class WarnOnce:
    """``WarnOnce(template)(*details)`` warns ``template.format(*details)`` (``RuntimeWarning``) the
    first time it is called, and does nothing afterwards until :meth:`reset`.

    Parameters
    ----------
    template : str
        The message, with a ``{}`` for each detail (e.g. the exception that caused a fallback).
    """

    def __init__(self, template: str):
        self.template = template
        self.issued = False

    def __call__(self, *details, stacklevel: int = 2) -> None:
        """Warn once; ``stacklevel`` as :func:`warnings.warn` would count it if called in place of
        this call (2: the caller of the function that calls this)."""
        if not self.issued:
            self.issued = True
            warnings.warn(self.template.format(*details), RuntimeWarning, stacklevel=stacklevel + 1)

    def reset(self) -> None:
        """Warn again at the next call."""
        self.issued = False
