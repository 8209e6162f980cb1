"""Pinned floating-point paths, so that an expert demo has the same bytes on every x86 machine.

Why: numpy picks SIMD kernels at run time (AVX2, AVX-512, ...), and its transcendental
and reduction kernels round differently on different CPUs. The experts' IK and motion
planning are closed loops over thousands of steps, so one ulp early on changes a long
demo's actions: ``CupboardsCloseAll`` seed 2 came out with other bytes on an AVX-512
machine than on the AVX2 machine that built dataset v1. With numpy held to its baseline
kernels and OpenBLAS to one kernel family and one thread, the same seed gives the same
file everywhere (all 15 tasks of v1 checked on an AVX-512 EPYC). The physics itself
(MuJoCo) and the env's arithmetic need no pinning: they are exact IEEE operations.

Both libraries read these settings only when they load, so generation runs in worker
processes started with :func:`pinned_environment`.
"""

from __future__ import annotations

import platform

from bigym.child_environment import child_environment

#: numpy's dispatch targets above the x86-64-v2 baseline (names of numpy >= 2.4 and older ones)
_NUMPY_FEATURES_ABOVE_BASELINE = (
    "X86_V3 X86_V4 AVX512_ICL AVX512_SPR AVX2 FMA3 AVX512F AVX512CD AVX512_KNL AVX512_KNM "
    "AVX512_SKX AVX512_CLX AVX512_CNL"
)


def _cpu_has_avx2_fma() -> bool:
    try:
        with open("/proc/cpuinfo") as info:
            flags = next((line for line in info if line.startswith("flags")), "").split()
    except OSError:
        return False
    return "avx2" in flags and "fma" in flags


def pinned_settings() -> dict[str, str]:
    """The environment variables that pin numpy's and OpenBLAS's kernels on this machine."""
    settings = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    if platform.machine().lower() in ("x86_64", "amd64"):
        settings["NPY_DISABLE_CPU_FEATURES"] = _NUMPY_FEATURES_ABOVE_BASELINE
        if _cpu_has_avx2_fma():  # the kernel family OpenBLAS picks on AVX2 CPUs without AVX-512
            settings["OPENBLAS_CORETYPE"] = "Haswell"
    return settings


def pinned_environment():
    """Set :func:`pinned_settings` in ``os.environ`` while worker processes are started
    (spawned children inherit it), and restore the previous values afterwards."""
    return child_environment(pinned_settings())


def numerics_pinned() -> bool:
    """Does numpy in this process run on its baseline kernels only (no run-time SIMD dispatch)?"""
    try:
        from numpy._core import _multiarray_umath as umath
    except ImportError:  # numpy < 2
        from numpy.core import _multiarray_umath as umath
    features = getattr(umath, "__cpu_features__", {})
    return not any(features.get(target) for target in getattr(umath, "__cpu_dispatch__", ()))
