"""wingmdao.groups."""
