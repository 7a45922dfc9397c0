"""Type stubs of the pushlab package (the native module pushlab._native)."""

import os
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, "os.PathLike[str]"]
_RecordingRef = Union["Recording", str]
F64 = npt.NDArray[np.float64]
Bools = npt.NDArray[np.bool_]

class PushlabError(Exception):
    """A file pushlab cannot read or write, or a value it cannot use; the message names the file,
    the line or field, and what was expected."""

class Recording:
    """One push: its frames as numpy arrays, its setting and its labels."""

    @property
    def name(self) -> str: ...
    @property
    def source(self) -> Path: ...
    @property
    def times(self) -> F64:
        """Seconds of each frame, shape (N,)."""
    @property
    def robot(self) -> F64:
        """The pusher's centre, world frame, metres, shape (N, 2)."""
    @property
    def object(self) -> F64:
        """The object's geometric centre and yaw (x, y, yaw), world frame, shape (N, 3)."""
    @property
    def setting(self) -> Dict[str, Any]:
        """setting.json's fields."""
    @property
    def labels(self) -> Optional[Dict[str, Bools]]:
        """Per-frame masks of the range labels painted on it; None without labels."""
    @property
    def events(self) -> List[Tuple[str, int]]: ...
    @property
    def meta(self) -> Dict[str, Any]: ...
    @property
    def skip(self) -> Bools:
        """True at frames labelled bad tracking, shape (N,)."""
    @property
    def warnings(self) -> List[str]:
        """Defects found while loading: rows dropped, gaps interpolated across, a file cut short."""
    @property
    def notes(self) -> List[str]:
        """What loading did that loses nothing: an angle unwrapped, streams put on one clock."""
    def __len__(self) -> int: ...

def load(paths: Union[_Path, Sequence[_Path]]) -> List[Recording]:
    """Every recording at the paths (sets, CSVs, MIT .json/.h5, bags and datasets with a remembered
    choice, folders of them), each with its folder's labels. Raises PushlabError naming every file
    that could not be read."""

class Labels:
    """A recording set's labels file, opened as pushlab's labels document."""

    def __init__(self, path: _Path) -> None:
        """Opens the labels file of a set folder (or the file itself)."""
    @property
    def path(self) -> Path: ...
    @property
    def schema(self) -> List[Dict[str, Any]]: ...
    @property
    def recordings(self) -> List[str]: ...
    @property
    def dirty(self) -> bool: ...
    def segments(self, recording: _RecordingRef) -> List[Tuple[str, int, int]]: ...
    def events(self, recording: _RecordingRef) -> List[Tuple[str, int]]: ...
    def meta(self, recording: _RecordingRef) -> Dict[str, Any]: ...
    def mask(self, recording: _RecordingRef, label: str, frames: Optional[int] = None) -> Bools: ...
    def masks(self, recording: _RecordingRef, frames: Optional[int] = None) -> Dict[str, Bools]: ...
    def paint(self, recording: _RecordingRef, label: str, start: int, end: int) -> bool: ...
    def erase(self, recording: _RecordingRef, start: int, end: int, label: Optional[str] = None) -> bool: ...
    def add_event(self, recording: _RecordingRef, label: str, frame: int) -> bool: ...
    def remove_event(self, recording: _RecordingRef, label: str, frame: int) -> bool: ...
    def set_meta(self, recording: _RecordingRef, field: str, value: Any) -> bool: ...
    def clear(self, recording: _RecordingRef) -> bool: ...
    def add_label(
        self,
        name: str,
        *,
        kind: str = "range",
        colour: str = "#808080",
        group: Optional[str] = None,
        hotkey: Optional[str] = None,
        skip_in_training: bool = False,
    ) -> bool: ...
    def remove_label(self, name: str, *, with_uses: bool = False) -> bool: ...
    def rename_label(self, old: str, new: str) -> bool: ...
    def save(self, *, overwrite: bool = False) -> None: ...
    def reload(self) -> None: ...

class Prediction:
    """How the object moves from `frame` to `frame + horizon`, object frame of `frame`."""

    frame: int
    theta: List[float]
    translation: List[float]
    rotation: float
    contact: Optional[List[float]]
    contact_motion: Optional[List[float]]
    observed_translation: List[float]
    observed_rotation: float
    loss_pos: float
    loss_rot: float
    def to_dict(self) -> Dict[str, Any]: ...

class OnlineRun:
    """Online learning of θ_online along one recording (pushlab eval's "online" pass)."""

    @property
    def theta(self) -> F64:
        """θ_online [com_x, com_y, h] in effect at each frame, metres, shape (N, 3)."""
    @property
    def std(self) -> F64:
        """The posterior's standard deviation of [com_x, com_y, h] at each frame, shape (N, 3)."""
    @property
    def losses(self) -> F64:
        """Online loss [pos, rot] per sample, NaN where θ was held, shape (N - horizon, 2)."""
    @property
    def fixed_losses(self) -> F64: ...
    @property
    def learned_frames(self) -> npt.NDArray[np.uintp]: ...
    @property
    def nmse(self) -> Dict[str, float]:
        """{"pos", "rot"}: the trajectory's `online` in pushlab eval --json."""
    @property
    def fixed_nmse(self) -> Dict[str, float]: ...
    @property
    def theta0(self) -> F64: ...
    @property
    def theta_end(self) -> F64: ...
    @property
    def com_offset_cov(self) -> F64: ...
    @property
    def h_std(self) -> float: ...
    @property
    def com_sigma_parts(self) -> Dict[str, float]:
        """What the COM's σ at the end is made of, metres: frames_m, misfit_m, drift_m."""
    @property
    def com_found(self) -> Optional[Dict[str, Any]]: ...
    @property
    def continued(self) -> bool:
        """Whether it went on from another run (`after=`) rather than from θ_online(0)."""
    @property
    def steps(self) -> int: ...
    @property
    def physics_only(self) -> bool:
        """Made by `model.physics_online`, not `model.online`."""

class Model:
    """A trained combined model (a pushlab model file)."""

    @staticmethod
    def load(path: _Path) -> "Model": ...
    @staticmethod
    def train(
        recordings: Sequence[Recording],
        *,
        kind: Optional[str] = None,
        horizon: Optional[int] = None,
        epochs: Optional[int] = None,
        seed: Optional[int] = None,
        patience: Optional[int] = None,
        adam_lr: Optional[float] = None,
        baseline: bool = False,
        com_calibration: bool = True,
    ) -> "Model": ...
    def save(self, path: _Path) -> None: ...
    @property
    def kind(self) -> str: ...
    @property
    def horizon(self) -> int: ...
    @property
    def has_baseline(self) -> bool: ...
    @property
    def training(self) -> Dict[str, Any]: ...
    def theta0(self, recording: Recording) -> F64: ...
    def predict(self, recording: Recording, frame: int, theta: Optional[Sequence[float]] = None) -> Prediction: ...
    def online(
        self,
        recording: Recording,
        optimizer: str = "gd",
        *,
        steps: int = 5,
        lr: float = 0.005,
        after: Optional[OnlineRun] = None,
        start_com_shift: Optional[Tuple[float, float]] = None,
    ) -> OnlineRun:
        """Online learning along `recording` from θ_online(0), or with `after` (a run on another
        push of the same object) from where that run ended, θ and its posterior, as
        `pushlab eval --carry-theta` does; a run on another object is refused (ValueError). With
        `start_com_shift` (x, y, metres), it starts believing the COM that far from θ_online(0)'s,
        the prior centred there, as `pushlab eval --start-com-shift` does."""
    def physics_online(
        self,
        recording: Recording,
        optimizer: str = "gd",
        *,
        contact_tolerance: float = 0.01,
        steps: int = 5,
        lr: float = 0.005,
        after: Optional[OnlineRun] = None,
        start_com_shift: Optional[Tuple[float, float]] = None,
    ) -> OnlineRun:
        """The physics-only model (the recording's outline and pusher, Lynch's model on the geometric
        contact, no network) learning θ_online online along `recording`, at this model's horizon with
        losses normalised by this model's offline σ: `pushlab eval --physics`'s "Physics online" pass
        (`contact_tolerance` metres is its `--contact-tolerance`), to the bit. The other arguments are
        `online`'s; `after` must be a physics-only run."""

    def best_fit(
        self, recording: Recording, *, physics: bool = False, contact_tolerance: float = 0.01
    ) -> Optional[Dict[str, Any]]:
        """The θ_online that fits the whole recording best, held fixed over it (a grid over the
        object, then Levenberg–Marquardt): what no online learner with this model beats on it, as
        `pushlab eval --best-fit` reports it — `theta` (`com_offset`, `h`), `nmse`, `mean_loss`,
        `samples` and, with a known COM, `com_error_m`; None without samples. With `physics=True`,
        the physics-only model's."""

def simulate(
    spec: Union[Dict[str, Any], _Path], *, out: Optional[_Path] = None, truth_labels: bool = False
) -> List[Recording]:
    """Recording sets from pushlab's simulator, with their true COM offset and h in the setting."""

class Controller:
    """Push to goal on poses a script gives: pushlab's controller (what `pushlab control --pipe`
    runs), learning θ from the poses as it goes."""

    def __init__(
        self,
        model: Model,
        setting: Union[Dict[str, Any], _Path],
        goal: Tuple[float, float, float],
        *,
        theta: str = "online",
        rate: float = 10.0,
        speed: float = 0.04,
    ) -> None: ...
    def step(
        self, t: float, pusher: Tuple[float, float], object: Tuple[float, float, float]
    ) -> Dict[str, Any]:
        """One control step on the poses at time t: its `target`, `phase`, `theta`, errors, …"""
    @property
    def done(self) -> bool:
        """Whether the goal is reached and held."""
    @property
    def theta(self) -> List[float]:
        """θ as learned so far, [com_x, com_y, h] in metres."""
