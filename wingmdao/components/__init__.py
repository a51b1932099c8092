"""wingmdao.components."""
