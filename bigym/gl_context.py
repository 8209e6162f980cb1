"""Offscreen OpenGL contexts that stay correct however envs are created, dropped and forked.

Two facts about OpenGL drive this module:

* ``mjr_freeContext`` deletes textures and framebuffers *by name in whichever context is
  current*, and names restart at 1 in every context. Freeing one renderer while another's
  context is current (what Python's garbage collector does when an env is dropped without
  ``close()``) deletes the other's buffers, and its images silently turn into noise. So
  an :class:`OffscreenGL` always frees its MjrContext inside its own GL context, and puts
  back whatever context was current before.
* A process forked after it initialised EGL inherits a display whose worker threads do not
  exist in the child: the child's first render hangs forever (gymnasium's
  ``AsyncVectorEnv`` builds one env in the parent before it forks its workers). So before
  any fork every open context is released and the EGL display is terminated; parent and
  child each reopen their contexts lazily at their next render. If a GL context that bigym
  does not own is alive (a user's own ``mujoco.Renderer``), the display is left alone and
  a forked child that tries to render gets a clear error instead of a hang.
"""

from __future__ import annotations

import gc
import os
import sys
import warnings
import weakref

import mujoco

# Contexts whose GL context could not be made current when they were released: kept alive
# (leaked) on purpose, because freeing them in another context would corrupt that context.
_UNRELEASABLE: list = []
# Every OffscreenGL with open GL resources, for the fork handler.
_OPEN: weakref.WeakSet[OffscreenGL] = weakref.WeakSet()
# Set in a forked child whose parent's EGL display could not be terminated before the fork.
_INHERITED_EGL_DISPLAY = False


def _new_gl_context(width: int, height: int):
    if _INHERITED_EGL_DISPLAY:
        raise RuntimeError(
            "cannot render in this process: it was forked from a process holding an EGL display that "
            "bigym could not release (an OpenGL context bigym does not own was alive, e.g. a "
            "mujoco.Renderer). Start workers with the 'spawn' or 'forkserver' method "
            "(e.g. gymnasium.vector.AsyncVectorEnv(..., context='spawn')), or close that renderer before forking."
        )
    try:
        context = mujoco.GLContext(width, height)
        context.make_current()
    except Exception as error:  # the GL backend raises several types; all mean "no GL here"
        backend = os.environ.get("MUJOCO_GL", "(unset)")
        raise RuntimeError(
            f"cannot create an OpenGL context for offscreen rendering (MUJOCO_GL={backend}): {error}. "
            "On a headless machine set MUJOCO_GL=egl (or osmesa)."
        ) from error
    return context


def _release(gl, mjr_context: mujoco.MjrContext) -> None:
    """Free ``mjr_context`` inside ``gl`` (restoring the previously current context), then ``gl``."""
    try:
        as_current = getattr(gl, "as_current", None)
        if as_current is not None:
            with as_current():
                mjr_context.free()
        else:  # older MuJoCo: nothing restores the previous context; renderers re-bind every frame
            gl.make_current()
            mjr_context.free()
    except Exception as error:  # noqa: BLE001 - never free in a foreign context: leak instead
        _UNRELEASABLE.append((gl, mjr_context))
        warnings.warn(f"could not release an offscreen GL context ({error}); its memory is kept", RuntimeWarning)
        return
    gl.free()


class OffscreenGL:
    """A GL context and one model's MjrContext drawing into an offscreen buffer.

    Safe to drop without :meth:`close`, to close twice, and to use on both sides of a fork.
    """

    def __init__(self, model: mujoco.MjModel, width: int, height: int) -> None:
        self._model = model
        self._size = (width, height)
        self._gl = None
        self._mjr_context: mujoco.MjrContext | None = None
        self._finalizer: weakref.finalize | None = None
        self._closed = False
        self._open()

    def _open(self) -> None:
        gl = _new_gl_context(*self._size)
        mjr_context = mujoco.MjrContext(self._model, mujoco.mjtFontScale.mjFONTSCALE_100)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, mjr_context)
        self._gl, self._mjr_context = gl, mjr_context
        # Runs on release or when this object is collected; it holds the only other
        # references, so neither GL object is destroyed (in the wrong context) before it.
        self._finalizer = weakref.finalize(self, _release, gl, mjr_context)
        _OPEN.add(self)

    def _release_resources(self) -> None:
        if self._finalizer is not None:
            self._finalizer()
        self._gl = self._mjr_context = self._finalizer = None
        _OPEN.discard(self)

    def make_current(self) -> mujoco.MjrContext:
        """Make this context current (reopening it after a fork) and return its MjrContext."""
        if self._gl is None:
            if self._closed:
                raise RuntimeError("this renderer is closed")
            self._open()
        self._gl.make_current()
        return self._mjr_context

    def close(self) -> None:
        """Release the GL resources now; idempotent."""
        self._closed = True
        self._release_resources()


def _owned_gl_contexts() -> set[int]:
    return {id(offscreen._gl) for offscreen in _OPEN if offscreen._gl is not None}


def _foreign_egl_context_alive(egl_module) -> bool:
    """Is an EGL context alive that no OffscreenGL owns? (Scans the heap: fork time only.)"""
    owned = _owned_gl_contexts()
    # Looking at every object can touch deprecated ones (torch's reduce_op warns): not ours to report.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return any(
            isinstance(obj, egl_module.GLContext) and getattr(obj, "_context", None) and id(obj) not in owned
            for obj in gc.get_objects()
        )


_display_released_for_fork = False


def _before_fork() -> None:
    global _display_released_for_fork
    _display_released_for_fork = False
    egl = sys.modules.get("mujoco.egl")
    if egl is None or egl.EGL_DISPLAY is None:
        return  # no EGL display: nothing a child could inherit
    if _foreign_egl_context_alive(egl):
        return
    for offscreen in list(_OPEN):
        offscreen._release_resources()  # reopened lazily at the next render, on both sides
    egl.EGL.eglTerminate(egl.EGL_DISPLAY)
    egl.EGL_DISPLAY = None
    _display_released_for_fork = True


def _after_fork_in_child() -> None:
    global _INHERITED_EGL_DISPLAY
    egl = sys.modules.get("mujoco.egl")
    _INHERITED_EGL_DISPLAY = egl is not None and egl.EGL_DISPLAY is not None and not _display_released_for_fork


if hasattr(os, "register_at_fork"):
    os.register_at_fork(before=_before_fork, after_in_child=_after_fork_in_child)
