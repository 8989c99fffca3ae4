"""Geometry: CRS facts and the PDS3 map-projection description of a raster grid."""
