"""pushlab from Python: recordings, labels, the combined push model and its online learning.

Every function is pushlab's core (the Rust crate ``pushlab-core``) called directly, so the numbers
are the CLI's and the app's: ``pushlab.load`` is the loader ``pushlab validate`` uses,
``Model.online`` is the online run ``pushlab eval`` reports, ``Labels`` is the app's labels document.
Arrays are numpy arrays in SI units (metres, radians, seconds). Errors raise ``PushlabError`` with
pushlab's own message, which names the file and the field.
"""

from ._native import (
    Controller,
    Labels,
    Model,
    OnlineRun,
    Prediction,
    PushlabError,
    Recording,
    __version__,
    load,
    simulate,
)

__all__ = [
    "Controller",
    "Labels",
    "Model",
    "OnlineRun",
    "Prediction",
    "PushlabError",
    "Recording",
    "__version__",
    "load",
    "simulate",
]
