"""The gallery renders every prop and scene plus a contact sheet."""

from __future__ import annotations

import numpy as np
from PIL import Image

from bigym.props import PROP_CLASSES
from bigym.props.gallery import HEIGHT, WIDTH, render_gallery
from bigym.scenes import scene_names


def test_render_gallery(tmp_path):
    paths = render_gallery(tmp_path / "gallery")
    n = len(PROP_CLASSES) + len(scene_names())
    assert len(paths) == n + 1
    assert paths[-1].name == "contact_sheet.png"
    assert {p.name for p in paths[:-1]} == {f"prop_{c}.png" for c in PROP_CLASSES} | {
        f"scene_{s}.png" for s in scene_names()
    }
    for p in paths[:-1]:
        img = np.asarray(Image.open(p))
        assert img.shape == (HEIGHT, WIDTH, 3), p.name
        # something was drawn: not a flat or black frame
        assert img.std() > 8.0 and img.mean() > 30.0, p.name
    sheet = Image.open(paths[-1])
    assert sheet.width == 6 * WIDTH and sheet.height >= (n // 6) * HEIGHT
