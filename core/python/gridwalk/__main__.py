"""python -m gridwalk: see gridwalk.cli."""
import sys

from .cli import main

sys.exit(main())
