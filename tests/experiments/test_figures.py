"""Smoke-run the figure and animation scripts at a small size and check that what they write is a picture.

Every figure of the paper must be written, listed in ``index.md`` under its caption, and not blank; the animations
(GIF, and ``mpa animate``) must have several distinct frames. Runs in well under a minute.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from tests.helpers.scripts import ROOT, run_script

PAPER = ROOT.parent / "shared" / "paper" / "lollipop-mpa.tex"
sys.path.insert(0, str(ROOT / "experiments"))

#: A figure is "not blank" if at least this fraction of its pixels is not white ...
MIN_INK = 0.01
#: ... and it uses at least this many distinct colours.
MIN_COLOURS = 8


def _ink(img: Image.Image) -> tuple[float, int]:
    arr = np.asarray(img.convert("RGB"), dtype=np.int16)
    ink = float(np.mean(np.any(arr < 245, axis=-1)))
    colours = len(np.unique(arr.reshape(-1, 3), axis=0))
    return ink, colours


@pytest.fixture(scope="module")
def figures_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("figures")
    res = run_script("experiments/figures.py", "--out", str(out), "--dpi", "40")
    assert res.returncode == 0, res.stderr
    return out


def test_every_figure_written_and_not_blank(figures_dir: Path) -> None:
    import figures

    assert len(figures.FIGURES) == 53
    for spec in figures.FIGURES:
        path = figures_dir / spec.filename
        assert path.is_file(), f"figure {spec.number} ({spec.caption}) missing: {path.name}"
        with Image.open(path) as img:
            ink, colours = _ink(img)
        assert ink > MIN_INK, f"{path.name} looks blank: {ink:.3%} non-white pixels"
        assert colours >= MIN_COLOURS, f"{path.name} looks blank: {colours} colours"
    assert not list(figures_dir.glob("*.tmp*")), "temporary files left behind"


def test_index_lists_every_caption_in_paper_order(figures_dir: Path) -> None:
    import figures

    index = (figures_dir / "index.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (\d+) \| (.*) \| \[(fig\d\d_\w+\.png)\]", index, flags=re.M)
    assert [int(n) for n, _, _ in rows] == list(range(1, 54))
    assert [f for _, _, f in rows] == [s.filename for s in figures.FIGURES]
    if PAPER.is_file():  # the captions, in the paper's order
        tex = PAPER.read_text(encoding="utf-8")
        # the paper's macro \A (\newcommand{\A}{\mathcal A}) written out, so that the index renders without it
        captions = [re.sub(r"\\A\b", r"\\mathcal{A}", c.strip()) for c in re.findall(r"\\caption\{(.*)\}", tex)]
        assert len(captions) == len(rows)
        for (_, cap, fname), paper_cap in zip(rows, captions):
            assert cap.replace("\\|", "|") == paper_cap, f"{fname}: {cap!r} != {paper_cap!r}"


def test_sample_queries_land_in_their_domains() -> None:
    import figures

    for name in figures.queries():
        p = figures.query_plan(name)  # raises if the domain is not the intended one
        assert any(s.u_end > s.u_start for s in p.steps if s.name == "preliminary"), f"{name}: empty preliminary"


def _frames(path: Path) -> list[np.ndarray]:
    with Image.open(path) as img:
        out = []
        for k in range(img.n_frames):
            img.seek(k)
            out.append(np.asarray(img.convert("RGB"), dtype=np.int16))
    return out


def test_animation_script_writes_moving_gifs(tmp_path: Path) -> None:
    res = run_script(
        "experiments/animate.py",
        "--out",
        str(tmp_path),
        "--dpi",
        "30",
        "--max-frames",
        "3",
        "--only",
        "circle_ex2",
        "lollipop_V2",
    )
    assert res.returncode == 0, res.stderr
    for name in ("circle_ex2", "lollipop_V2"):
        frames = _frames(tmp_path / f"{name}.gif")
        assert len(frames) == 3
        assert float(np.mean(np.any(frames[0] < 245, axis=-1))) > MIN_INK
        assert np.any(frames[0] != frames[-1]), f"{name}: the animation does not move"


def test_cli_animate_and_its_errors(tmp_path: Path) -> None:
    from trajopt.cli import main

    # the circle's domain-1 example (conventions: Domains of continuity)
    query = ["animate", "--track", "circle", "--start", "0.3", "0.6", "--goal", "0.25", "0.1"]
    out = tmp_path / "anim"
    assert main([*query, "--out", str(out), "--dpi", "30", "--max-frames", "2", "--raw-only"]) == 0
    assert len(_frames(out / "animation.gif")) == 2
    bad = tmp_path / "bad"
    rc = main(["animate", "--track", "circle", "--start", "0.3", "0.6", "--goal", "0.25", "1.5", "--out", str(bad)])
    assert rc == 2
    assert not bad.exists(), "an error left an output directory behind"
    rc = main([*query, "--out", str(bad), "--fps", "0"])
    assert rc == 2
    assert not bad.exists()


def test_mp4_needs_ffmpeg_or_says_so(tmp_path: Path) -> None:
    from mpa import Circle, InvalidInputError, plan
    from trajopt.viz.animation import animate_motions, ffmpeg_executable, plan_motion

    p = plan(Circle(1.0), (0.3, 0.6), (0.25, 0.1))
    target = tmp_path / "a.mp4"
    if ffmpeg_executable() is None:
        with pytest.raises(InvalidInputError, match="ffmpeg"):
            animate_motions(p.track, [plan_motion(p, 0.5)], target, plan=p, dpi=30, max_frames=2)
        assert not target.exists()
    else:
        animate_motions(p.track, [plan_motion(p, 0.5)], target, plan=p, dpi=30, max_frames=2)
        assert target.stat().st_size > 1000


def test_architecture_layers_hold_and_the_picture_is_drawn(tmp_path: Path) -> None:
    import architecture

    assert architecture.check_layers() == []
    res = run_script("experiments/architecture.py", "--out", str(tmp_path / "arch.png"), "--dpi", "30")
    assert res.returncode == 0, res.stderr
    with Image.open(tmp_path / "arch.png") as img:
        ink, colours = _ink(img)
    assert ink > MIN_INK and colours >= MIN_COLOURS


def test_a_layer_violation_is_reported(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import architecture

    fake = tmp_path / "mpa"
    fake.mkdir()
    (fake / "bad.py").write_text("import matplotlib\nfrom trajopt import generator\n", encoding="utf-8")
    monkeypatch.setattr(architecture, "ROOT", tmp_path)
    problems = architecture.check_layers()
    assert any("mpa.bad imports matplotlib" in p for p in problems), problems
    assert any("mpa.bad imports trajopt from the layer above" in p for p in problems), problems
