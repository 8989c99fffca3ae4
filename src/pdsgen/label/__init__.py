"""Writing PDS3 label text: value encoding, line layout and template rendering."""
