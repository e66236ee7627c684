"""Caliper: metrically accurate, rigged 3-D avatars from a few body measurements (docs/python.md).

The whole API is the compiled module caliper._caliper (python/caliper_module.cpp); this file only
re-exports it, so `import caliper` is all a script needs.
"""
from ._caliper import *  # noqa: F401,F403
from ._caliper import __doc__, __version__  # noqa: F401
