"""The kernel decorator: caching keyed on every kernel source, and the switch to turn it off."""

import os
import subprocess
import sys

import pytest

from hairbed._core import _jit


def test_kernels_carry_the_package_cache():
    from hairbed._core._kernels import branch

    if not _jit.CACHE_ENABLED or os.environ.get("NUMBA_DISABLE_JIT") == "1":
        pytest.skip("caching is off in this run")
    cache = branch.evaluate._cache
    assert isinstance(cache, _jit._KernelCache)
    # the stamp that invalidates the cache is the hash of all kernel sources, not one file
    assert cache._impl.locator.get_source_stamp() == _jit.kernel_sources_hash()


def test_source_hash_changes_with_any_kernel_file(tmp_path, monkeypatch):
    (tmp_path / "a.py").write_text("x = 1\n")
    (tmp_path / "b.py").write_text("y = 2\n")
    monkeypatch.setattr(_jit, "_KERNEL_DIR", tmp_path)
    _jit.kernel_sources_hash.cache_clear()
    try:
        first = _jit.kernel_sources_hash()
        _jit.kernel_sources_hash.cache_clear()
        (tmp_path / "b.py").write_text("y = 3\n")  # an edit of a callee's file
        second = _jit.kernel_sources_hash()
    finally:
        _jit.kernel_sources_hash.cache_clear()
    assert first != second


@pytest.mark.parametrize("value, enabled", [("0", False), ("off", False), ("1", True)])
def test_environment_switch(value, enabled):
    env = dict(os.environ, HAIRBED_NUMBA_CACHE=value)
    code = "import hairbed._core._jit as j; print(j.CACHE_ENABLED)"
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    assert out.stdout.strip() == str(enabled)
