"""Formats: bytes on disk, no mission knowledge (raster reading, nodata, DN scaling,
IMG streaming, JPEG 2000, GeoJP2, GeoJSON footprints, staged outputs, file heads,
file checksums)."""
