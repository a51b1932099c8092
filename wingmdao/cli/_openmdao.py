"""Imported first by the commands that run OpenMDAO problems of their own (``size``, ``n2``):
OpenMDAO loads here, without the matplotlib of its report plugins
(:func:`wingmdao.utils.memory.import_openmdao_without_plot_plugins`; the problems ask for no
reports, and a plot loads matplotlib when it draws)."""

from wingmdao.utils.memory import import_openmdao_without_plot_plugins

import_openmdao_without_plot_plugins()
