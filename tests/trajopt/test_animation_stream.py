"""``mpa animate``'s renderer: fixed layout, moving artists blitted, frames streamed, a progress bar on a terminal."""

from __future__ import annotations

import io
import itertools
import os
import stat
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from mpa import Lollipop, plan
from trajopt.viz import animation as A


def _motions() -> tuple[object, list[A.Motion]]:
    p = plan(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2))
    return p, [A.plan_motion(p, 0.5)]


def test_gif_frames_show_the_moving_robots(tmp_path: Path) -> None:
    p, motions = _motions()
    out = A.animate_motions(p.track, motions, tmp_path / "a.gif", plan=p, dpi=40, max_frames=6, progress=False)
    with Image.open(out) as im:
        assert im.n_frames == 6
        frames = []
        for k in range(im.n_frames):
            im.seek(k)
            frames.append(np.asarray(im.convert("RGB"), dtype=int))
    assert all(f.shape == frames[0].shape for f in frames)
    # consecutive frames differ (the robots, the trail and the clock move), but only in part of the picture
    # (colours compared with a tolerance: PIL decodes the first frame of these GIFs with white 255, the others 252)
    for f0, f1 in itertools.pairwise(frames):
        changed = np.any(np.abs(f0 - f1) > 8, axis=2)
        assert 0 < changed.mean() < 0.2
    # the moving artists are drawn on top of the background: the first and last frames differ where the dot is
    assert np.any(np.abs(frames[0] - frames[-1]) > 8)
    assert not list(tmp_path.glob(".*tmp*"))


def test_progress_bar_only_when_asked_or_on_a_terminal(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    p, motions = _motions()
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    A.animate_motions(p.track, motions, tmp_path / "a.gif", plan=p, dpi=30, max_frames=4)  # not a tty: quiet
    assert err.getvalue() == ""
    A.animate_motions(p.track, motions, tmp_path / "b.gif", plan=p, dpi=30, max_frames=4, progress=True)
    text = err.getvalue()
    assert "4/4 frames" in text and text.endswith("\n")


def test_mp4_frames_are_streamed_as_raw_pixels(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A stand-in ffmpeg that stores its raw input: every frame arrives, with the announced size."""
    fake = tmp_path / "ffmpeg"
    fake.write_text(
        "#!" + sys.executable + "\n"
        "import sys\n"
        "args = sys.argv[1:]\n"
        "size = args[args.index('-s') + 1]\n"
        "data = sys.stdin.buffer.read()\n"
        "open(args[-1], 'wb').write(size.encode() + b'\\n' + data)\n",
        encoding="utf-8",
    )
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("PATH", f"{tmp_path}{os.pathsep}{os.environ.get('PATH', '')}")
    p, motions = _motions()
    out = A.animate_motions(p.track, motions, tmp_path / "a.mp4", plan=p, dpi=30, max_frames=5, progress=False)
    head, _, data = out.read_bytes().partition(b"\n")
    w, h = (int(x) for x in head.decode().split("x"))
    assert w % 2 == 0 and h % 2 == 0
    assert len(data) == 5 * w * h * 4
