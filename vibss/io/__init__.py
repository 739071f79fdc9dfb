"""Model files (TOML and JSON) to and from :class:`vibss.Model`, and the built-in examples."""

from .modelfile import *  # noqa: F401,F403
from .modelfile import __all__
