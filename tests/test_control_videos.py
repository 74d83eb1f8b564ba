"""bench/control_videos.py (bench/control_robots.py --video) on the quick Atlas: the push case run
closed and open loop, its still (two rows of frames, one camera) and its MP4s (each run, and both
side by side), written to a temporary folder."""
import numpy as np
import pytest

pytest.importorskip("imageio_ffmpeg")

from conftest import bench_module  # noqa: E402


@pytest.fixture(scope="module")
def videos():
    return bench_module("control_videos")


def test_atlas_push_still_and_videos(videos, tmp_path, monkeypatch):
    from hovi.examples.paper import build, report
    example = build("atlas", quick=True)
    result = report.solve(example)
    assert result.success
    monkeypatch.setattr(videos, "IMAGE_DIR", str(tmp_path / "images"))
    monkeypatch.setattr(videos, "VIDEO_DIR", str(tmp_path / "videos"))
    monkeypatch.setitem(videos.SLOW, "atlas", 2)            # 16 frames a run: a smoke run
    out = videos.write("atlas", example, result)
    assert out["closed_loop"]["success"] and not out["open_loop"]["success"]   # the open loop's contact step fails
    assert out["push"] == {"time": 0.15, "body": "pelvis", "impulse": [20.0, 0.0, 0.0]}
    still = tmp_path / "images" / "control_atlas.png"
    assert still.exists() and still.stat().st_size < 150_000
    import imageio.v2 as imageio
    image = imageio.imread(still)
    assert image.shape[:2] == (400, 880)                     # 5 frames of 2.2 in by two rows, 80 dpi
    assert np.ptp(image[..., :3]) > 100                      # drawn, not blank
    for name, width in (("atlas_push_closed_loop", 640), ("atlas_push_open_loop", 640), ("atlas_push", 1280)):
        with imageio.get_reader(str(tmp_path / "videos" / f"{name}.mp4")) as reader:
            frames = [np.asarray(f) for f in reader]
        assert frames[0].shape == (480, width, 3)
        # the motion at 2 x 25 frames per second of motion (0.3 s; the open loop stops at 0.25 s), the last held 1 s
        assert len(frames) >= 13 + 25
