"""Process memory helpers (no OpenMDAO)."""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import os


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
