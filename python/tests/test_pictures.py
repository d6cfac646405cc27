"""The inline picture, the GIF and the plots are valid images of the scene."""

import io

import numpy as np
import pytest

import sprung

Image = pytest.importorskip("PIL.Image")


def decoded(data):
    image = Image.open(io.BytesIO(data))
    image.load()
    return image


def test_the_inline_picture_is_the_scene(scenes):
    world = sprung.load(scenes / "ball3d.toml")
    png = world._repr_png_()
    image = decoded(png)
    assert image.format == "PNG" and image.size == (640, 480)
    pixels = np.asarray(image.convert("RGB"), dtype=np.int32)
    # Not blank: the ball's springs and faces make many colours.
    assert len(np.unique(pixels.reshape(-1, 3), axis=0)) > 20
    small = decoded(world.picture(200, 100))
    assert small.size == (200, 100)
    # The picture moves with the world.
    world.step(3000)
    assert world._repr_png_() != png


def test_the_gif_plays_the_run(scenes):
    world = sprung.load(scenes / "ball2d.toml")
    gif = sprung.animate(world, time=0.4, fps=10, width=160, height=120)
    assert world.steps == 0  # animated on a copy
    image = decoded(gif.data)
    assert image.format == "GIF" and image.size == (160, 120)
    # 0.4 s at 10 pictures a second: the start and 4 more.
    assert image.n_frames == 5
    frames = []
    for k in range(image.n_frames):
        image.seek(k)
        frames.append(np.asarray(image.convert("RGB")))
    assert not np.array_equal(frames[0], frames[-1])  # the ball fell
    assert '<img src="data:image/gif;base64,' in gif._repr_html_()


def test_the_plots_of_a_run(scenes, tmp_path):
    table = sprung.run(scenes / "ball2d.toml", steps=400)
    plots = sprung.plot(table, width=400, height=300)
    assert list(plots) == ["energy", "gas"]
    for png in plots.values():
        image = decoded(png.data)
        assert image.size == (400, 300)
        pixels = np.asarray(image.convert("RGB"))
        assert len(np.unique(pixels.reshape(-1, 3), axis=0)) > 5
    sprung.run(scenes / "rope.toml", steps=50, out=tmp_path)
    assert list(sprung.plot(tmp_path)) == ["energy"]  # no gas
