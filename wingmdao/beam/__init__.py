"""wingmdao.beam."""
