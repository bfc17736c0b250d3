"""The on-disk cache of converted Open-RMF maps (:mod:`mpa.openrmf.cache`): a hit is the conversion, anything else
is converted again."""

from __future__ import annotations

import json
import random
from pathlib import Path
from typing import Any

import pytest
import yaml

import mpa.openrmf.building as building
from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack
from mpa.openrmf import read_layout_file
from mpa.openrmf.cache import CACHE_ENV, cache_dir, entry_key

DATA = Path(__file__).resolve().parents[1] / "data" / "openrmf"
MAPS = [
    (DATA / "office.building.yaml", "L1", None),
    (DATA / "hotel.building.yaml", "L1", None),
    (DATA / "hotel.building.yaml", "L2", None),
    (DATA / "hotel.building.yaml", "L3", None),
    (DATA / "airport_terminal.building.yaml", "L1", 2),
]
AIRPORT = MAPS[-1]
HOTEL_L2 = MAPS[2]


def _fresh(path: Path, level: str | None, nav: int | None, monkeypatch: pytest.MonkeyPatch) -> Any:
    monkeypatch.setenv(CACHE_ENV, "off")
    out = read_layout_file(path, level, nav)
    return json.loads(json.dumps(list(out)))


def _entries(d: Path) -> list[Path]:
    return sorted(d.glob("*.json"))


def _no_conversion(monkeypatch: pytest.MonkeyPatch) -> None:
    def fail(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError("converted although the cache holds the map")

    monkeypatch.setattr(building, "building_layout", fail)
    monkeypatch.setattr(building, "nav_graph_layout", fail)


@pytest.mark.parametrize(("path", "level", "nav"), MAPS, ids=[f"{p.name}:{lv}" for p, lv, _ in MAPS])
def test_a_hit_is_the_conversion_and_converts_nothing(
    path: Path, level: str, nav: int | None, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    fresh = _fresh(path, level, nav, monkeypatch)
    monkeypatch.setenv(CACHE_ENV, str(tmp_path))
    first = read_layout_file(path, level, nav)
    assert list(first) == fresh
    assert len(_entries(tmp_path)) == 1
    _no_conversion(monkeypatch)
    second = read_layout_file(path, level, nav)
    assert list(second) == fresh
    a = GraphTrack.from_layout(fresh[0])
    b = GraphTrack.from_file(path, level, nav)
    assert a.to_dict() == b.to_dict() and a.coords == b.coords and a.points == b.points


def _damage(entry: Path, how: str, rng: random.Random) -> None:
    data = entry.read_bytes()
    head, _, body = data.partition(b"\n")
    header = json.loads(head)
    if how == "truncated":
        entry.write_bytes(data[: rng.randrange(len(data))])
    elif how == "byte":
        i = rng.randrange(len(data))
        entry.write_bytes(data[:i] + bytes([data[i] ^ (1 << rng.randrange(8))]) + data[i + 1 :])
    elif how == "other key":
        header["key"] = "0" * 64
        entry.write_bytes(json.dumps(header).encode() + b"\n" + body)
    elif how == "old format":
        header["format"] = "mpa-layout-cache 0"
        entry.write_bytes(json.dumps(header).encode() + b"\n" + body)
    elif how == "not a layout, digest right":
        import hashlib

        fake = json.dumps([{"edges": "x"}, {}]).encode()
        header["sha256"] = hashlib.sha256(fake).hexdigest()
        entry.write_bytes(json.dumps(header).encode() + b"\n" + fake)
    elif how == "garbage":
        entry.write_bytes(bytes(rng.randrange(256) for _ in range(300)))
    elif how == "empty":
        entry.write_bytes(b"")
    else:  # pragma: no cover
        raise ValueError(how)


@pytest.mark.parametrize(
    "how", ["truncated", "byte", "other key", "old format", "not a layout, digest right", "garbage", "empty"]
)
def test_a_damaged_or_stale_entry_is_converted_again_and_rewritten(
    how: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path, level, nav = HOTEL_L2
    fresh = _fresh(path, level, nav, monkeypatch)
    monkeypatch.setenv(CACHE_ENV, str(tmp_path))
    read_layout_file(path, level, nav)
    (entry,) = _entries(tmp_path)
    good = entry.read_bytes()
    rng = random.Random(f"cache {how}")
    for trial in range(8 if how in ("truncated", "byte", "garbage") else 1):
        _damage(entry, how, rng)
        got = list(read_layout_file(path, level, nav))
        assert got == fresh, f"{how}, trial {trial}: a damaged entry was trusted"
        assert entry.read_bytes() == good, f"{how}, trial {trial}: the entry was not rewritten whole"


def test_the_key_follows_the_text_the_level_the_graph_and_the_format(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    text = (DATA / "hotel.building.yaml").read_text(encoding="utf-8")
    keys = {
        entry_key(text, "L1", None),
        entry_key(text, "L2", None),
        entry_key(text, "L1", 0),
        entry_key(text + " ", "L1", None),
    }
    assert len(keys) == 4
    assert entry_key(text, "L1", None) == entry_key(text, "L1", None)
    # an edited map (a lane moved) is converted, not read from the old entry
    monkeypatch.setenv(CACHE_ENV, str(tmp_path))
    copy = tmp_path / "map.building.yaml"
    copy.write_text(text, encoding="utf-8")
    before = read_layout_file(copy, "L1")
    data = yaml.safe_load(text)
    level = data["levels"]["L1"]
    level["vertices"][level["lanes"][0][0]][0] += 1.0
    copy.write_text(yaml.safe_dump(data), encoding="utf-8")
    after = read_layout_file(copy, "L1")
    monkeypatch.setenv(CACHE_ENV, "off")
    assert list(after) == json.loads(json.dumps(list(read_layout_file(copy, "L1"))))
    assert after[0] != before[0]
    assert len(_entries(tmp_path)) == 2


def test_errors_and_json_layouts_are_not_cached(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    d = tmp_path / "cache"
    monkeypatch.setenv(CACHE_ENV, str(d))
    for _ in range(2):
        with pytest.raises(InvalidInputError, match="L9"):
            read_layout_file(DATA / "hotel.building.yaml", "L9")
    layout = tmp_path / "layout.json"
    layout.write_text(json.dumps({"edges": [{"name": "e", "from": "a", "to": "b", "length": 2}]}), encoding="utf-8")
    out, info = read_layout_file(layout)
    assert info == {"kind": "layout"} and out["edges"][0]["length"] == 2
    assert not d.exists() or _entries(d) == []


def test_an_unwritable_cache_leaves_the_map_converted(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    blocker = tmp_path / "not a directory"
    blocker.write_text("x")
    path, level, nav = AIRPORT
    fresh = _fresh(path, level, nav, monkeypatch)
    monkeypatch.setenv(CACHE_ENV, str(blocker / "cache"))
    assert list(read_layout_file(path, level, nav)) == fresh
    assert list(tmp_path.iterdir()) == [blocker]


def test_the_cache_directory(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for off in ("off", "", " "):
        monkeypatch.setenv(CACHE_ENV, off)
        assert cache_dir() is None
    monkeypatch.setenv(CACHE_ENV, str(tmp_path / "c"))
    assert cache_dir() == tmp_path / "c"
    monkeypatch.delenv(CACHE_ENV)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_dir() == tmp_path / "xdg" / "lollipop-mpa" / "layouts"
    monkeypatch.delenv("XDG_CACHE_HOME")
    assert cache_dir() == Path.home() / ".cache" / "lollipop-mpa" / "layouts"

    def no_home() -> Path:
        raise RuntimeError("Could not determine home directory.")

    monkeypatch.setattr(Path, "home", staticmethod(no_home))
    assert cache_dir() is None
    path, level, nav = HOTEL_L2
    assert read_layout_file(path, level, nav)[1]["kind"] == "building"


def test_the_command_line_plans_the_same_from_the_cache(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from trajopt.cli.main import main

    path, level, nav = AIRPORT
    args = ["plan", "--graph", str(path), "--level", level, "--nav-graph", str(nav), "--clearance", "0.6"]
    args += ["--start", "lane70:3.102", "lane143:8.848", "--goal", "lane87:1.237", "lane100:0.997", "--json"]
    outs = []
    for env in ("off", str(tmp_path), str(tmp_path)):
        monkeypatch.setenv(CACHE_ENV, env)
        assert main(args) == 0
        outs.append(json.loads(capsys.readouterr().out))
    for o in outs:
        o.pop("compute_ms", None)
        o.pop("time_ms", None)
    assert outs[0] == outs[1] == outs[2]
    assert len(_entries(tmp_path)) == 1


def test_a_reinstalled_pyyaml_gives_new_keys(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.machinery
    import importlib.util

    import mpa.openrmf.cache as cache

    keys = []
    for i, body in enumerate(["# one", "# another version"]):
        fake = tmp_path / f"yaml{i}" / "__init__.py"
        fake.parent.mkdir()
        fake.write_text(body)
        spec = importlib.machinery.ModuleSpec("yaml", None, origin=str(fake))
        monkeypatch.setattr(importlib.util, "find_spec", lambda name, package=None, s=spec: s)
        monkeypatch.setattr(cache, "_SOURCE_DIGEST", [])
        keys.append(entry_key("levels: {}", "L1", None))
    assert keys[0] != keys[1]
