"""Process memory helpers (no OpenMDAO)."""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import os
import sys


def return_freed_memory() -> bool:
    """Collect garbage and ask the C allocator to return freed heap pages to the operating system
    (glibc ``malloc_trim(0)``), so a later phase of a run starts from the memory in use rather than
    from the high-water mark of the one before. False where there is no glibc (macOS, musl)."""
    gc.collect()
    name = ctypes.util.find_library("c")
    try:
        return bool(ctypes.CDLL(name).malloc_trim(0)) if name else False
    except (OSError, AttributeError):
        return False


#: glibc ``mallopt`` parameters (``malloc.h``)
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
#: the user's own settings of them, which take precedence (glibc reads them at start-up)
_MALLOC_VARIABLES = ("MALLOC_TRIM_THRESHOLD_", "MALLOC_MMAP_THRESHOLD_", "GLIBC_TUNABLES")


def return_large_blocks_on_free(mmap_threshold: int = 1 << 17) -> bool:
    """Ask glibc to serve every block of ``mmap_threshold`` bytes or more with its own mapping and
    to trim the heap's free top at once, so a freed large array goes back to the operating system
    when it is freed.

    glibc's default raises the mapping threshold to the size of any mapped block that is freed (up
    to 32 MB); after that, the arrays of a time history (MB each) are carved out of the heap, whose
    freed holes are reused only by blocks that fit them, and the resident set grows with every
    design point a sizing analyses. A fixed threshold keeps the resident set at the memory in use.
    Nothing is changed when the user set glibc's own variables (``MALLOC_MMAP_THRESHOLD_``,
    ``MALLOC_TRIM_THRESHOLD_``, ``GLIBC_TUNABLES``).

    Parameters
    ----------
    mmap_threshold : int, optional
        Block size (bytes) from which glibc maps each block on its own.

    Returns
    -------
    bool
        True when both settings were made; False where there is no glibc (macOS, musl) or the user
        chose.
    """
    if any(name in os.environ for name in _MALLOC_VARIABLES):
        return False
    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name) if name else None
        mallopt = libc.mallopt if libc is not None else None
    except (OSError, AttributeError):
        return False
    if mallopt is None:
        return False
    return bool(mallopt(_M_MMAP_THRESHOLD, int(mmap_threshold))) and bool(mallopt(_M_TRIM_THRESHOLD, 0))


def import_openmdao_without_plot_plugins() -> bool:
    """Import OpenMDAO for a command-line run that asks for no OpenMDAO reports, without the
    matplotlib its start-up loads for those reports (~30 MB resident).

    Two things in OpenMDAO import ``matplotlib.pyplot`` whether or not a plot is ever drawn:
    ``openmdao.drivers.modopt_driver`` reads matplotlib's backend when ``openmdao.api`` is imported
    (to restore it after importing the optional modOpt), and the first ``om.Problem()`` loads the
    report plugins (``openmdao_report`` entry points), whose optimization report imports pyplot at
    module level. Here matplotlib is hidden while ``openmdao.api`` is imported (the modOpt driver
    then finds neither matplotlib nor modOpt, which wingmdao does not use) and the report plugins
    are marked loaded (``openmdao.utils.reports_system._plugins_loaded``). A later plot imports
    matplotlib as usual. Only the ``wingmdao`` command calls this, whose problems are built with
    ``reports=False``: a library user's process keeps OpenMDAO's behaviour.

    Returns
    -------
    bool
        True when OpenMDAO was imported here without matplotlib; False when OpenMDAO or matplotlib
        was already imported (nothing is changed) or OpenMDAO no longer has the plugin flag.
    """
    if "openmdao.api" in sys.modules or "matplotlib" in sys.modules:
        return False
    sys.modules["matplotlib"] = None  # `import matplotlib` raises ImportError while this is set
    try:
        import openmdao.api  # noqa: F401
    finally:
        del sys.modules["matplotlib"]
    from openmdao.utils import reports_system

    if not hasattr(reports_system, "_plugins_loaded"):
        return False
    reports_system._plugins_loaded = True
    return True
