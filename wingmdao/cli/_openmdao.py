"""Imported first by each command module that loads OpenMDAO: OpenMDAO loads here, without the
matplotlib of its report plugins (:func:`wingmdao.utils.memory.import_openmdao_without_plot_plugins`:
~0.6 s CPU less; the commands' problems ask for no reports, and a plot loads matplotlib when it
draws)."""

from wingmdao.utils.memory import import_openmdao_without_plot_plugins

import_openmdao_without_plot_plugins()
