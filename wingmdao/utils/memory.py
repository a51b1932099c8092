"""Process memory helpers (no OpenMDAO)."""

from __future__ import annotations

import ctypes
import ctypes.util
import gc


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
