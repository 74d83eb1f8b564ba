"""Screenshots of HTML files with a headless Chromium (Debian's `chromium`, installed by `make test`'s set-up)."""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

BROWSERS = ("chromium", "chromium-browser", "google-chrome")


def browser() -> str:
    """The browser's path; skips the test with the reason when there is none or it cannot start."""
    path = next((shutil.which(b) for b in BROWSERS if shutil.which(b)), None)
    if path is None:
        pytest.skip("no headless browser: install Debian's chromium (scripts/setup.sh test does)")
    try:
        subprocess.run([path, "--headless", "--no-sandbox", "--version"], capture_output=True, timeout=60, check=True)
    except (subprocess.SubprocessError, OSError) as e:
        pytest.skip(f"{path} cannot start headless: {e}")
    return path


def screenshot(html: Path, out: Path, fragment: str = "", size=(640, 480)) -> np.ndarray:
    """(height, width, 3) uint8 pixels of `html` (with `#fragment`) rendered by software WebGL."""
    from PIL import Image

    cmd = [browser(), "--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
           "--hide-scrollbars", f"--window-size={size[0]},{size[1]}", "--virtual-time-budget=3000",
           f"--screenshot={out}", html.resolve().as_uri() + (f"#{fragment}" if fragment else "")]
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert out.is_file(), f"no screenshot written: {run.stderr[-2000:]}"
    return np.asarray(Image.open(out).convert("RGB"))


def changed_fraction(a: np.ndarray, b: np.ndarray, threshold: int = 40) -> float:
    """Fraction of pixels whose colour differs by more than `threshold` in some channel."""
    return float(np.mean(np.abs(a.astype(int) - b.astype(int)).max(axis=2) > threshold))
