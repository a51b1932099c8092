"""The argument parsers of the ``wingmdao`` commands: one module per command module of
:mod:`wingmdao.cli`, of the same name, with ``register(subparsers, argv=None)``.

A parser module imports argparse, the shared flags (:mod:`wingmdao.cli._args`) and names and
defaults from :mod:`wingmdao.names` only, so ``wingmdao COMMAND --help`` loads neither OpenMDAO
nor CasADi. Each parser's ``func`` names the function that runs it, ``"wingmdao.cli.MODULE:FUNCTION"``;
:func:`wingmdao.cli.main` imports that module (and with it the numerical stack) only once the
command line has parsed. ``argv`` (the command line) lets a command whose cases each bring their
own options (``size CASE``) build the parser of the named case only (None: every case's).
"""
