"""PDS3 labels both ways, on one grammar (grammar.py): reading (lexer.py, parser.py -> tree.py;
read.py: the END rule and a file's label head; beside.py: files a label names) and writing
(values.py, layout.py, render.py)."""
