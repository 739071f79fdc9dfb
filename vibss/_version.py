"""The package version, written once (vibss.__version__, the CLI's --version, the report's footer)."""

__version__ = "0.1.0"
