"""Movie files of the animations: the formats, the writers (a streaming GIF writer, ffmpeg's h264 for MP4), the
progress bar, and the frames handed to a writer into a file written atomically.

Shared by :mod:`trajopt.viz.animation` (the paper's tracks) and :mod:`trajopt.viz.layout_animation` (layouts).
"""

from __future__ import annotations

import math
import shutil
import sys
import time
from pathlib import Path
from typing import Any

import matplotlib as mpl
import numpy as np
from matplotlib.animation import AbstractMovieWriter, FFMpegWriter
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from numpy.typing import NDArray
from PIL import GifImagePlugin, Image

from mpa.errors import InvalidInputError
from trajopt.io.atomic import atomic_path

#: Output formats and their file suffixes.
FORMATS = {"gif": ".gif", "mp4": ".mp4"}


def ffmpeg_executable() -> str | None:
    """Path of an ffmpeg executable: on the PATH, else the one inside ``imageio-ffmpeg``, else None."""
    exe = shutil.which("ffmpeg")
    if exe:
        return exe
    try:
        import imageio_ffmpeg
    except ImportError:
        return None
    try:
        return str(imageio_ffmpeg.get_ffmpeg_exe())
    except (RuntimeError, OSError):  # pragma: no cover - a broken install
        return None


def animation_format(out: Path, fmt: str | None) -> str:
    """The animation format: ``fmt``, else the suffix of ``out`` (InvalidInputError unless one of :data:`FORMATS`)."""
    fmt = fmt if fmt is not None else out.suffix.lstrip(".").lower()
    if fmt not in FORMATS:
        raise InvalidInputError(f"format is {fmt!r}, expected one of {sorted(FORMATS)}")
    return fmt


def validate_number(name: str, value: object, lo: float, *, integer: bool = False) -> float:
    """``value`` as a float when it is a finite number ``>= lo`` (an integer if ``integer``), else
    InvalidInputError naming ``name``, the value and what was expected."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InvalidInputError(f"{name} is {value!r}, expected a number >= {lo:g}")
    v = float(value)
    if not (math.isfinite(v) and v >= lo) or (integer and not v.is_integer()):
        what = "an integer" if integer else "a finite number"
        raise InvalidInputError(f"{name} is {value!r}, expected {what} >= {lo:g}")
    return v


def validate_movie_options(
    out: Path, fmt: str | None, fps: object, dpi: object, max_frames: object
) -> tuple[str, float, float, int | None]:
    """The options every animation takes, validated: ``(format, fps, dpi, max_frames)``.

    ``format`` from :func:`animation_format`; ``fps`` (frames per second) ``>= 1``; ``dpi`` ``>= 10``;
    ``max_frames`` None or an integer ``>= 2``. InvalidInputError naming the first bad one.
    """
    fmt = animation_format(out, fmt)
    fps_ = validate_number("fps", fps, 1.0)
    dpi_ = validate_number("dpi", dpi, 10.0)
    frames = None if max_frames is None else int(validate_number("max_frames", max_frames, 2.0, integer=True))
    return fmt, fps_, dpi_, frames


def frame_times(t0: float, t1: float, fps: float, max_frames: int | None) -> tuple[NDArray[np.float64], float]:
    """Times of the frames from ``t0`` to ``t1`` (s, shape (F,), both ends included) at ``fps`` frames per second,
    at most ``max_frames`` of them, and how much faster than real time they play (1 unless capped)."""
    n = math.ceil((t1 - t0) * fps) + 1
    speedup = 1.0
    if max_frames is not None and n > max_frames:
        speedup = (n - 1) / max(max_frames - 1, 1)
        n = int(max_frames)
    return np.linspace(t0, t1, max(n, 1)), speedup


def movie_writer(fmt: str, fps: float, ffmpeg_fps: float | None = None) -> Any:
    """The writer of an animation: a streaming GIF writer at ``fps``, or ffmpeg's h264 at ``ffmpeg_fps`` (default
    ``fps``); InvalidInputError for mp4 without an ffmpeg executable."""
    if fmt == "gif":
        return StreamingGifWriter(fps=fps)
    exe = ffmpeg_executable()
    if exe is None:
        raise InvalidInputError(
            "format is 'mp4', which needs an ffmpeg executable: install one (pip install imageio-ffmpeg) or use gif"
        )
    mpl.rcParams["animation.ffmpeg_path"] = exe
    rate = fps if ffmpeg_fps is None else ffmpeg_fps
    return FFMpegWriter(fps=rate, codec="libx264", extra_args=["-pix_fmt", "yuv420p"])  # type: ignore[arg-type]


class _Progress:
    """A one-line progress bar on stderr (``\\r``-updated at most 10 times a second); silent unless enabled.

    Parameters
    ----------
    total : int
        Number of steps.
    label : str
    enabled : bool, optional
        Default: when stderr is a terminal.
    """

    def __init__(self, total: int, label: str, enabled: bool | None = None) -> None:
        self.total, self.label = max(int(total), 1), label
        stream = sys.stderr
        self.enabled = bool(enabled) if enabled is not None else bool(getattr(stream, "isatty", lambda: False)())
        self.t0 = time.perf_counter()
        self._last = -1.0
        self.shown = 0

    def update(self, done: int) -> None:
        """``done`` steps finished."""
        if not self.enabled:
            return
        now = time.perf_counter()
        if done < self.total and now - self._last < 0.1:
            return
        self._last = now
        frac = min(done / self.total, 1.0)
        el = now - self.t0
        eta = el / frac - el if frac > 0 else 0.0
        bar = "#" * int(30 * frac) + "-" * (30 - int(30 * frac))
        sys.stderr.write(f"\r{self.label}: [{bar}] {done}/{self.total} frames, {el:5.1f} s, {eta:5.1f} s left")
        sys.stderr.flush()
        self.shown += 1

    def close(self) -> None:
        """End the line."""
        if self.enabled and self.shown:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _save_streaming(fig: Figure, frames: Any, out: Path, fmt: str, writer: Any, dpi: float, bar: _Progress) -> None:
    """Hand every frame to the writer as it is drawn, into a temporary file beside ``out``, then rename it; nothing
    is left on a failure. ``frames`` yields after each frame has been drawn onto the figure's canvas."""
    out.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(out, suffix=FORMATS[fmt]) as tmp, writer.saving(fig, str(tmp), dpi):
        for k in frames:
            _grab(writer, fig)
            bar.update(k + 1)


def _grab(writer: Any, fig: Figure) -> None:
    """Give the writer the canvas as drawn (no redraw: the frame was blitted onto the background)."""
    canvas = fig.canvas
    rgba = np.asarray(canvas.buffer_rgba())  # type: ignore[attr-defined]
    if hasattr(writer, "write_rgba"):
        writer.write_rgba(rgba)
    else:  # FFMpegWriter: raw RGBA into the pipe
        writer._proc.stdin.write(rgba.tobytes())


class StreamingGifWriter(AbstractMovieWriter):
    """A GIF writer that encodes and writes each frame as it is grabbed (memory flat in the number of frames).

    The palette (up to 256 colours, no dithering) is taken from the first frame and reused for every frame, so colours
    do not flicker. Loops forever.
    """

    def __init__(self, fps: float = 20.0) -> None:
        super().__init__(fps=round(fps) if fps >= 1 else 1)
        self._fps = float(fps)
        self._fp: Any = None
        self._palette: Image.Image | None = None
        self._last: NDArray[np.uint8] = np.zeros((0, 0), dtype=np.uint8)
        self.frames = 0

    def setup(self, fig: Figure, outfile: str | Path, dpi: float | None = None) -> None:
        """Open ``outfile`` for writing."""
        super().setup(fig, outfile, dpi=dpi)
        self._fp = open(outfile, "wb")
        self._palette = None
        self.frames = 0

    def grab_frame(self, **savefig_kwargs: Any) -> None:
        """Render the figure and append it to the file (only the rectangle that changed since the last frame)."""
        fig = self.fig
        fig.set_dpi(self.dpi)
        canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
        canvas.draw()
        self.write_rgba(np.asarray(canvas.buffer_rgba()))

    def write_rgba(self, rgba: NDArray[np.uint8]) -> None:
        """Append one frame given as pixels (shape (H, W, 4)), e.g. a canvas drawn by blitting."""
        rgb = Image.fromarray(rgba[..., :3].copy(), "RGB")
        duration = round(1000.0 / self._fps)
        if self._palette is None:
            self._palette = rgb.quantize(colors=256, dither=Image.Dither.NONE)
            frame = self._palette
            header, _ = GifImagePlugin.getheader(frame, None, {"loop": 0, "duration": duration})
            for chunk in header:
                self._fp.write(chunk)
            box = (0, 0, frame.width, frame.height)
        else:
            frame = rgb.quantize(palette=self._palette, dither=Image.Dither.NONE)
            changed = np.asarray(frame) != self._last
            if changed.any():
                rows, cols = np.nonzero(changed.any(axis=1))[0], np.nonzero(changed.any(axis=0))[0]
                box = (int(cols[0]), int(rows[0]), int(cols[-1]) + 1, int(rows[-1]) + 1)
            else:
                box = (0, 0, 1, 1)
        self._last = np.asarray(frame).copy()
        part = frame.crop(box)
        part.palette = frame.palette
        for chunk in GifImagePlugin.getdata(part, (box[0], box[1]), duration=duration):
            self._fp.write(chunk)
        self.frames += 1

    def finish(self) -> None:
        """Write the GIF trailer and close the file."""
        if self._fp is not None:
            self._fp.write(b";")
            self._fp.close()
            self._fp = None
