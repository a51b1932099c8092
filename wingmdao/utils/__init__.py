"""wingmdao.utils."""
