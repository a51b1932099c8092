"""Independent verification models (3-D solid finite elements of the wing-like box beam)."""
