"""pdsgen: planetary terrain models and orthoimages to PDS3 archive products."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("pdsgen")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+source"

__all__ = ["__version__"]
