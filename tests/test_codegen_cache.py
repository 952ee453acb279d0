"""The size bound of the compiled-library cache (mbsym.codegen_cache): least recently used first.

References: file sizes and modification times set here (the order and the bytes pruning must reach are
known exactly), and the compiler's own libraries for the end-to-end checks.
"""

import os
import time

import casadi as ca
import pytest

from mbsym.codegen import compile_function, find_compiler
from mbsym.codegen_cache import DEFAULT_LIMIT_MB, limit_bytes, prune, usage
from mbsym.exceptions import OptionError

needs_cc = pytest.mark.skipif(find_compiler() is None, reason="no C compiler on this machine")


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("MBSYM_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("MBSYM_CACHE_MAX_MB", raising=False)
    monkeypatch.delenv("MBSYM_NO_COMPILE", raising=False)


def _library(folder, name, size, age_s):
    path = folder / name
    path.write_bytes(b"\0" * size)
    t = time.time() - age_s
    os.utime(path, (t, t))
    return path


def test_prune_deletes_least_recently_used_down_to_ninety_percent(tmp_path):
    libs = [_library(tmp_path, f"f{i}_0123.so", 1000, age_s=100 - i) for i in range(10)]     # f0 oldest
    other = _library(tmp_path, "notes.txt", 5000, age_s=1000)
    removed = prune(tmp_path, limit=6000)
    # 10000 bytes above a 6000-byte bound: the oldest go until 5400 (90 %) are left, i.e. five
    assert removed == libs[:5]
    assert [p for _, _, p in usage(tmp_path)] == libs[5:]
    assert other.exists()                      # not a library: never touched
    assert prune(tmp_path, limit=6000) == []   # within the bound: nothing more


def test_prune_keeps_the_library_just_built(tmp_path):
    libs = [_library(tmp_path, f"g{i}.so", 1000, age_s=10 - i) for i in range(3)]
    removed = prune(tmp_path, keep=libs[0], limit=1500)
    assert libs[0].exists() and removed == libs[1:]


def test_stale_build_directories_go_running_ones_stay(tmp_path):
    stale, running = tmp_path / "mbsym_cg_old", tmp_path / "mbsym_cg_new"
    for d in (stale, running):
        d.mkdir()
        (d / "big.c").write_text("int x;")
    t = time.time() - 3600
    os.utime(stale, (t, t))
    prune(tmp_path, limit=1e9, stale_after=1200)
    assert not stale.exists() and running.exists()


def test_limit_from_the_environment(monkeypatch):
    assert limit_bytes() == DEFAULT_LIMIT_MB * 1e6
    monkeypatch.setenv("MBSYM_CACHE_MAX_MB", "250")
    assert limit_bytes() == 250e6
    monkeypatch.setenv("MBSYM_CACHE_MAX_MB", "inf")
    assert limit_bytes() == float("inf")
    for bad in ("0", "-5", "lots", "nan"):
        monkeypatch.setenv("MBSYM_CACHE_MAX_MB", bad)
        with pytest.raises(OptionError, match="MBSYM_CACHE_MAX_MB.*positive number of megabytes"):
            limit_bytes()


def _function(name, k):
    x = ca.SX.sym("x")
    return ca.Function(name, [x], [ca.sin(x) * k + x ** 2])


@needs_cc
def test_compile_function_keeps_the_cache_within_its_bound(monkeypatch, tmp_path):
    first = compile_function(_function("lru_a", 1.0))
    size = first.library.stat().st_size
    monkeypatch.setenv("MBSYM_CACHE_MAX_MB", str(1.5 * size / 1e6))       # room for one library
    second = compile_function(_function("lru_b", 2.0))
    assert second.compiled and second.library.exists()
    assert not first.library.exists()                                        # the least recently used went
    # loading from the cache counts as a use: the loaded library outlives a newer, unused one
    third = compile_function(_function("lru_c", 3.0))
    assert not second.library.exists() and third.library.exists()
    t = time.time() - 100
    os.utime(third.library, (t, t))
    again = compile_function(_function("lru_c", 3.0))
    assert again.cache_hit and again.library.stat().st_mtime > t + 50


@needs_cc
def test_a_bad_bound_is_refused_before_any_work(monkeypatch, tmp_path):
    monkeypatch.setenv("MBSYM_CACHE_MAX_MB", "-1")
    with pytest.raises(OptionError, match="MBSYM_CACHE_MAX_MB"):
        compile_function(_function("lru_bad", 1.0))
    assert not (tmp_path / "cache").exists() or not any((tmp_path / "cache").iterdir())
