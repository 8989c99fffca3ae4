"""pdsgen: planetary terrain models and orthoimages to PDS3 archive products."""

# Single source of the version: pyproject.toml reads it from here (hatch), and
# SOFTWARE_NAME in every label states it.
__version__ = "0.1.0"

__all__ = ["__version__"]
