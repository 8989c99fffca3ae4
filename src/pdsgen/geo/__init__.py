"""Geometry: both directions between a raster grid and a label's map projection, and the
facts they rest on.

geometry.py       grid + CRS -> PDS3 IMAGE_MAP_PROJECTION keywords (MapGeometry)
label_georef.py   a label's map projection object (PDS3, or a VICAR MAP group) -> CRS and grid
conventions.py    the PDS3 offset convention both ways (projection_offsets, upper_left_corner),
                  longitude wraps and the west-positive flip
transverse_mercator.py  the folded Transverse Mercator grid's label note: written and read back
utm.py            UTM's scale factor, false origin and zone arithmetic
"""
