"""The animation page (`lagrange animate`) in a real browser: headless Chromium, driven by
Playwright as a user drives it — clicking on the time slider and on Play. Each page must load
without an error logged, draw the mechanism (not a blank canvas), redraw where the bodies moved
when the slider seeks, move the error plot's cursor, and play.

Run by scripts/browser-check, from `cargo test --workspace` (crates/cli/tests/cli/browser.rs), with
LAGRANGE_BIN naming the binary under test (default: the release build). The screenshot of the four-bar that the README shows is written to
target/browser/four_bar.png.
"""

import io
import os
import pathlib
import subprocess

import pytest
from PIL import Image, ImageChops
from playwright.sync_api import sync_playwright

ROOT = pathlib.Path(__file__).resolve().parents[2]
BINARY = os.environ.get("LAGRANGE_BIN", str(ROOT / "target" / "release" / "lagrange"))
OUT = ROOT / "target" / "browser"
# Chromium as root in a container: no sandbox; no background networking (this machine's
# network is closed, and a page that fetched anything would be a defect of its own).
ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
        "--disable-sync", "--no-first-run"]

# (scene, extra arguments): a closed loop, a rope over a pulley, rolling on an incline, a spring,
# a chain, a driven support, a joint-graph file and a coordinates-form file, and a normal mode.
PAGES = {
    "four_bar": ["four_bar", "--t-end", "4"],
    "atwood": ["atwood", "--t-end", "2"],
    "rolling_disc": ["rolling_disc", "--t-end", "2"],
    "harmonic_oscillator": ["harmonic_oscillator", "--t-end", "2"],
    "chain": ["chain", "--t-end", "3"],
    "driven_pendulum": ["driven_pendulum", "--t-end", "3"],
    "slider_crank_file": [str(ROOT / "examples" / "scenes" / "slider_crank.graph.toml"), "--t-end", "2"],
    "four_bar_coordinates_file": [str(ROOT / "examples" / "scenes" / "four_bar.toml"), "--t-end", "2"],
    "double_pendulum_mode": ["double_pendulum", "--mode", "1", "--q", "0,0", "--amplitude", "0.3"],
}


@pytest.fixture(scope="session")
def browser():
    with sync_playwright() as p:
        chromium = p.chromium.launch(executable_path="/usr/bin/chromium", args=ARGS)
        yield chromium
        chromium.close()


def write_page(name):
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / f"{name}.html"
    subprocess.run([BINARY, "animate", *PAGES[name], "--out", str(path)], check=True, capture_output=True)
    return path


def grab(page, selector):
    return Image.open(io.BytesIO(page.locator(selector).screenshot())).convert("RGB")


def ink(image):
    """The number of pixels that are not the white background."""
    return sum(1 for p in image.getdata() if min(p) < 235)


def seek_by_click(page, fraction):
    """Click on the time slider at `fraction` of its width, as a user does."""
    page.locator("#time").scroll_into_view_if_needed()
    box = page.locator("#time").bounding_box()
    page.mouse.click(box["x"] + fraction * box["width"], box["y"] + box["height"] / 2)
    return page.evaluate("window.lagrange.time()")


def changed_near(before, after, point, radius):
    x, y = (int(round(v)) for v in point)
    box = (max(x - radius, 0), max(y - radius, 0), min(x + radius, before.width), min(y + radius, before.height))
    return ImageChops.difference(before.crop(box), after.crop(box)).getbbox() is not None


@pytest.mark.parametrize("name", sorted(PAGES))
def test_page_draws_seeks_and_plays(browser, name):
    path = write_page(name)
    page = browser.new_page(viewport={"width": 1200, "height": 900}, device_scale_factor=1)
    problems = []
    page.on("console", lambda m: problems.append(f"console {m.type}: {m.text}") if m.type in ("error", "warning") else None)
    page.on("pageerror", lambda e: problems.append(f"page error: {e}"))
    page.on("request", lambda r: problems.append(f"request: {r.url}") if not r.url.startswith("file:") else None)
    page.goto(path.as_uri())
    t0, t_end = page.evaluate("[window.lagrange.t0, window.lagrange.tEnd]")
    span = t_end - t0
    assert span > 0

    # Two times picked on the slider: the clock follows it (to a slider step and a thumb's
    # width, 3 % of the span).
    t1 = seek_by_click(page, 0.2)
    assert abs(t1 - (t0 + 0.2 * span)) < 0.03 * span, (t1, t0, t_end)
    first, first_plot = grab(page, "#view"), grab(page, "#errors")
    t2 = seek_by_click(page, 0.7)
    assert abs(t2 - (t0 + 0.7 * span)) < 0.03 * span, (t2, t0, t_end)
    second, second_plot = grab(page, "#view"), grab(page, "#errors")

    # Not blank: the mechanism and the ground take ink; the plot has axes and curves.
    assert ink(first) > 300 and ink(second) > 300, "a blank drawing"
    assert ink(first_plot) > 1000, "a blank error plot"
    # The drawing changed where a body moved by more than a few pixels, and the plot's
    # cursor moved.
    bodies = len(page.evaluate("window.lagrange.data.bodies"))
    label = page.evaluate("window.lagrange.data.tracks.find(t => t.times.length > 0).label")
    moved = 0
    for body in range(bodies):
        a = page.evaluate(f"window.lagrange.pixel({label!r}, {t1}, {body})")
        b = page.evaluate(f"window.lagrange.pixel({label!r}, {t2}, {body})")
        if (a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2 > 8 ** 2:
            moved += 1
            assert changed_near(first, second, a, 4), f"body {body} left {a} but the drawing there did not change"
            assert changed_near(first, second, b, 4), f"body {body} reached {b} but the drawing there did not change"
    assert moved > 0, "no body moved between the two times"
    assert ImageChops.difference(first_plot, second_plot).getbbox() is not None, "the plot's cursor did not move"

    # Playing advances the clock and the drawing; pausing stops both.
    page.locator("#play").click()
    page.wait_for_timeout(600)
    page.locator("#play").click()
    paused_at = page.evaluate("window.lagrange.time()")
    assert paused_at != t2, "playing did not advance the time"
    assert not page.evaluate("window.lagrange.playing()")
    page.wait_for_timeout(200)
    assert page.evaluate("window.lagrange.time()") == paused_at, "the time moved while paused"

    if name == "four_bar":
        seek_by_click(page, 0.5)
        page.screenshot(path=str(OUT / "four_bar.png"))
    assert not problems, problems
    page.close()
