"""The validator's rule families, one module each (FILE, SYNTAX, DICT, PTR and REC, IMG,
MAP, GEO, HRSC, IMARS, SET); the rule table in `..registry` ties them to stable ids."""
