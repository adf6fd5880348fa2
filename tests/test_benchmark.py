"""The shared benchmark (hairbed._benchmark): structure only, never timings."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys

import pytest

from hairbed import _benchmark


def test_rows_are_typed_and_compared_with_their_targets():
    rows = _benchmark.run(quick=True, rows={1, 2, 4}, n=300, repeat=1)
    assert [r.number for r in rows] == ["1", "2", "4"]
    for r in rows:
        assert isinstance(r, _benchmark.Row)
        label, unit, target, op = _benchmark.ROWS[r.number]
        assert (r.label, r.unit, r.target, r.op) == (label, unit, target, op)
        assert r.value > 0
        assert r.passed == (r.value <= target)
    with pytest.raises(dataclasses.FrozenInstanceError):
        rows[0].value = 1.0  # type: ignore[misc]
    assert _benchmark.Row.of("6", 150.0).passed is True
    assert _benchmark.Row.of("10c", 0.3).passed is None
    assert _benchmark.Row.of("10c", 0.3).verdict == "info"


def test_report_json_and_progress(tmp_path):
    said = []
    result = _benchmark.measure(True, {3, 9}, said.append, n=100, repeat=1)
    assert [r.number for r in result.rows] == ["3", "9"]
    assert said[0].startswith("warm-up") and any("row 9" in m for m in said)
    text = _benchmark.format_report(result)
    assert "QUICK" in text and _benchmark.ROWS["9"][0] in text
    path = tmp_path / "b.json"
    _benchmark.write_json(result, path)
    data = json.loads(path.read_text())
    assert data["meta"]["rows"] == [3, 9]
    assert [r["row"] for r in data["rows"]] == ["3", "9"]
    assert list(tmp_path.iterdir()) == [path]


@pytest.mark.parametrize(
    "kwargs", [{"rows": {0}}, {"rows": {12}}, {"rows": set()}, {"repeat": 0}, {"n": 0}]
)
def test_bad_arguments(kwargs):
    with pytest.raises(ValueError):
        _benchmark.run(quick=True, **kwargs)


def test_imports_only_numpy_and_hairbed():
    code = (
        "import sys, hairbed._benchmark\n"
        "bad = [m for m in ('matplotlib', 'scipy.special') if m in sys.modules]\n"
        "assert not bad, bad"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)
