"""PDS3 labels both ways, on one grammar (grammar.py): reading (parser.py: text -> tree.py, and
the END rule; read.py: a label file whole; beside.py: files a label names; mapping.py: the
tree as plain values) and writing (values.py, layout.py, render.py)."""
