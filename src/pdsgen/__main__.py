"""`python -m pdsgen` runs the command-line interface."""

from .cli import main

main()
