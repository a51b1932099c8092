"""Stiffened panels: laminates, plate and column buckling, crippling, ribs (docs/panels.md)."""
