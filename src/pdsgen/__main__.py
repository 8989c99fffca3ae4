"""`python -m pdsgen` runs the command-line interface.

It runs under the name `pdsgen`, so its messages and shell completion
(`_PDSGEN_COMPLETE`) are those of the installed command.
"""

from .cli import run

run(prog_name="pdsgen")
