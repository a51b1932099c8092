import sys

from wingmdao.cli import main

sys.exit(main())
