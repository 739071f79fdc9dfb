"""What the user describes: bodies, mount types, mounts, loads, excitations, units and geometry.

Everything here is frozen, validated data; edits return copies. Nothing here computes a response.
"""

from .model import *  # noqa: F401,F403  (the public model vocabulary: Body, Mount, Model ...)
from .model import __all__
