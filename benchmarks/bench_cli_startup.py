"""CPU time of ``wingmdao COMMAND --help`` for every command, and which heavy frameworks it loads.

    PYTHONPATH=. python benchmarks/bench_cli_startup.py [--repeat 5] [--baseline DIR] [--json PATH] [COMMAND ...]

Each figure is the best of ``--repeat`` fresh processes of the ``wingmdao`` console script's code
(``wingmdao.cli.main``), user + system CPU time of the child process (``resource.getrusage``), so
interpreter start-up is included. ``loads`` lists the heavy frameworks (OpenMDAO's problem API,
CasADi, SciPy, matplotlib) in ``sys.modules`` after the help was printed. ``-`` is ``wingmdao
--help`` itself. ``--baseline DIR`` also times the checkout in DIR (e.g. ``git archive REV wingmdao |
tar -x -C DIR``), its processes interleaved with the current one's so both see the same load.

Figures (CPU s, best of 5; 2-core machine shared with other jobs, load ~10;
``git archive 0be6c8f wingmdao | tar -x -C /tmp/base; OMP_NUM_THREADS=1 PYTHONPATH=. python
benchmarks/bench_cli_startup.py --baseline /tmp/base``): ``baseline`` is the code whose command
modules built their parsers after importing OpenMDAO, CasADi and SciPy; ``now`` loads none of them
(the parsers of ``wingmdao.cli.parsers``)::

    command     baseline  now
    -             0.16   0.13
    cache         0.47   0.13
    export        1.39   0.14
    flutter       1.13   0.13
    gust          0.95   0.13
    loads         1.19   0.13
    maneuver      0.96   0.15
    panel         0.49   0.13
    report        1.01   0.13
    run           1.37   0.14
    section       0.50   0.15
    section-fe    0.70   0.14
    size          1.42   0.14
    n2            1.51   0.14
    turbulence    0.86   0.14
    verify        1.37   0.15

``-`` is ``wingmdao --help``. ``wingmdao size CASE --help`` imports the case's module for its options
table (same command with the argument ``"size pegasus"``): ``size pegasus`` 1.45 s baseline, 0.91 s now
(CasADi and SciPy, no OpenMDAO).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys

from wingmdao.cli import COMMANDS

#: the frameworks whose import ``--help`` should not pay
HEAVY = ("openmdao.api", "openmdao.core.problem", "casadi", "scipy", "matplotlib")

_CHILD = ("import sys\n"
          "from wingmdao.cli import main\n"
          "try:\n"
          "    code = main(sys.argv[1:])\n"
          "except SystemExit as exc:\n"
          "    code = exc.code\n"
          "sys.stderr.write('\\nLOADED ' + ' '.join(m for m in {heavy!r} if m in sys.modules) + '\\n')\n"
          "sys.exit(code or 0)\n")


def commands() -> list:
    """The command names of ``wingmdao --help``.

    Returns
    -------
    list of str
        :data:`wingmdao.cli.COMMANDS`' names.
    """
    return list(COMMANDS)


def help_cpu(command: str | None, root: str) -> tuple:
    """CPU time of one fresh process of ``wingmdao [COMMAND] --help``.

    Parameters
    ----------
    command : str or None
        The command, with its case after a space (``"size pegasus"``); None: ``wingmdao --help``.
    root : str
        The folder holding the ``wingmdao`` package to time (put first on ``PYTHONPATH``).

    Returns
    -------
    tuple
        (user + system CPU time in s, the heavy frameworks loaded).
    """
    argv = (command.split() if command else []) + ["--help"]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [root, os.environ.get("PYTHONPATH")])))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, "-c", _CHILD.format(heavy=HEAVY), *argv], capture_output=True,
                         text=True, env=env, cwd=root)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode:
        raise SystemExit(f"wingmdao {' '.join(argv)} failed in {root}:\n{out.stderr}")
    return (after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime,
            out.stderr.rsplit("LOADED", 1)[-1].strip())


def main(argv=None) -> int:
    """Print each command's ``--help`` CPU time.

    Parameters
    ----------
    argv : sequence of str, optional
        The command line (default ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit code.
    """
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("commands", nargs="*", help="the commands, with a case after a space ('size pegasus'; default: all, and '-' for wingmdao --help)")
    parser.add_argument("--repeat", type=int, default=5, help="fresh processes per command (best is kept)")
    parser.add_argument("--baseline", metavar="DIR", help="also time the wingmdao package in DIR (interleaved)")
    parser.add_argument("--json", metavar="PATH", help="also write the figures as JSON")
    args = parser.parse_args(argv)
    names = args.commands or ["-"] + commands()
    roots = {"now": os.getcwd(), **({"baseline": os.path.abspath(args.baseline)} if args.baseline else {})}
    result = {}
    print(f"{'command':<12} " + " ".join(f"{k + ' CPU s':>16}" for k in reversed(roots)) + "  heavy frameworks loaded")
    for name in names:
        best = {k: (float("inf"), "") for k in roots}
        for _ in range(args.repeat):
            for key, root in roots.items():
                cpu, loaded = help_cpu(None if name == "-" else name, root)
                best[key] = (min(best[key][0], cpu), loaded)
        result[name] = {k: {"cpu_s": round(v[0], 3), "loads": v[1].split()} for k, v in best.items()}
        print(f"{name:<12} " + " ".join(f"{best[k][0]:16.3f}" for k in reversed(roots))
              + "  " + " | ".join(best[k][1] or "-" for k in reversed(roots)), flush=True)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(result, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
