"""PDS3 labels both ways, on one grammar (grammar.py): reading (parser.py: text -> tree.py, the
END rule and LabelFile, a label file read once; tree.py: the tree, its pointers and the questions
asked of it; read.py: read_pds3_label and the per-run LabelCache; beside.py: files a label names;
mapping.py: the tree as plain values or as a mapping view) and writing (values.py, layout.py,
render.py)."""
