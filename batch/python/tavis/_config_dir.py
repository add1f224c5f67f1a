"""Where the robot and policy-key configs are when ``config_dir`` is not given."""

import os

from . import _tavis


def default_config_dir():
    """The configs installed beside the package (pip, cmake --install), else
    <prefix>/share/tavis/configs for a package at <prefix>/lib/python/tavis (the portable bundle,
    docs/bundle.md), else the source tree's configs of the build that made the module."""
    package = os.path.dirname(os.path.abspath(__file__))
    installed = os.path.join(package, "configs")
    if os.path.isdir(installed):
        return installed
    prefix = os.path.dirname(os.path.dirname(os.path.dirname(package)))
    bundled = os.path.join(prefix, "share", "tavis", "configs")
    if os.path.isdir(os.path.join(bundled, "robots")):
        return bundled
    return _tavis.DEFAULT_CONFIG_DIR
