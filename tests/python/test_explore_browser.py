"""npend explore's page in a real browser (headless Chromium driven by Selenium): the map's
pixels are `npend map`'s cells, zooming asks for the deeper tiles, a click animates the
pendulum of that cell with its bobs where Chain.positions puts them, and the address
reproduces the view. NPEND_EXPLORE_SCREENSHOT=FILE saves a picture of the page."""

import math
import os
import shutil
import time
import urllib.parse

import numpy as np
import pytest

from conftest import run_npend
from explore_fixture import explore_server

try:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
except ImportError:  # pragma: no cover - tools/setup.sh --test installs it
    webdriver = None


@pytest.fixture
def browser():
    if webdriver is None or shutil.which("chromedriver") is None:
        pytest.fail("the browser tests need python3-selenium, chromium and chromium-driver "
                    "(bash tools/setup.sh --test)")
    options = webdriver.ChromeOptions()
    for flag in ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                 "--window-size=1300,1000", "--force-device-scale-factor=1"]:
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
    try:
        yield driver
    finally:
        driver.quit()


def wait_for(driver, script, timeout=120):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if driver.execute_script(script):
            return
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {script}; page error: "
                         f"{driver.execute_script('return window.npendExplore && npendExplore.error')}")


# An asymmetric window (a turned or mirrored picture would not match) with cells that flip,
# cells that do not by t_end (white) and cells the energy rules out (grey).
VIEW = {"links": "2", "t-end": "8", "dt": "0.01", "cells": "16", "xname": "phi1",
        "xfrom": "-1", "xto": "3", "yname": "phi2", "yfrom": "-3", "yto": "0.5"}


def pixel(driver, canvas_id, x, y):
    return driver.execute_script(
        "return Array.from(document.getElementById(arguments[0]).getContext('2d')"
        ".getImageData(arguments[1], arguments[2], 1, 1).data)", canvas_id, int(x), int(y))


def test_the_page_draws_zooms_animates_and_keeps_its_address(browser, tmp_path):
    import npend

    with explore_server("--no-cache") as base:
        browser.get(f"{base}/#" + urllib.parse.urlencode(VIEW))
        wait_for(browser, "return window.npendExplore && npendExplore.done()")
        assert browser.execute_script("return npendExplore.error") == ""

        # At zoom 0, 4 x 4 tiles cover the window: each one's values are npend map's, and
        # each cell's pixel has the colour its value calls for, the right way up.
        keys = browser.execute_script(
            "return npendExplore.visibleTiles().map(t => npendExplore.tileKey(t, 16))")
        assert len(keys) == 16
        kinds = set()
        cells = {}
        for k, key in enumerate(keys):
            query = dict(urllib.parse.parse_qsl(key))
            run_npend("map", "--links", "2", "--x", query["x"], "--y", query["y"], "--t-end", "8",
                      "--out", tmp_path / f"m{k}")
            expected = np.load(tmp_path / f"m{k}" / "map.npy")
            mask = tmp_path / f"m{k}" / "forbidden.npy"
            forbidden = np.load(mask) if mask.exists() else np.zeros((16, 16), np.uint8)
            shown = browser.execute_script(
                "return Array.from(npendExplore.tiles.get(arguments[0]).values).map(String)", key)
            assert np.array_equal(np.array([float(v) for v in shown]).reshape(16, 16), expected,
                                  equal_nan=True)
            x_axis, y_axis = query["x"].split(":"), query["y"].split(":")
            for j in range(16):
                for i in range(16):
                    x = float(x_axis[1]) + (float(x_axis[2]) - float(x_axis[1])) * i / 15
                    y = float(y_axis[1]) + (float(y_axis[2]) - float(y_axis[1])) * j / 15
                    cells[(x, y)] = expected[j, i]
                    px, py = browser.execute_script(
                        "return npendExplore.toCanvas(arguments[0], arguments[1])", x, y)
                    r, g, b, _ = pixel(browser, "map", px, py)
                    v = expected[j, i]
                    if forbidden[j, i]:
                        kind, ok = "grey", (r, g, b) == (160, 160, 160)
                    elif v == math.inf:
                        kind, ok = "white", (r, g, b) == (255, 255, 255)
                    elif math.isnan(v):
                        kind, ok = "red", (r, g, b) == (214, 39, 40)
                    else:
                        kind, ok = "colour", (r, g, b) not in [(160, 160, 160), (255, 255, 255)]
                    kinds.add(kind)
                    assert ok, (k, i, j, v, (r, g, b))
        assert {"grey", "white", "colour"} <= kinds

        # Zoom twice about the centre: a quarter of the window, in tiles of level 2 + 2.
        base_width = 4.0
        for _ in range(2):
            browser.execute_script("npendExplore.zoomAt(256, 256, 0.5)")
        wait_for(browser, "return npendExplore.done()")
        view = browser.execute_script("return npendExplore.view")
        assert view["x1"] - view["x0"] == pytest.approx(base_width / 4)
        tiles = browser.execute_script(
            "return npendExplore.visibleTiles().map(t => [t.z, npendExplore.tileKey(t, 16)])")
        assert len(tiles) == 16 and all(z == 4 for z, _ in tiles)
        for _, key in tiles:
            x = dict(urllib.parse.parse_qsl(key))["x"].split(":")
            cell = (float(x[2]) - float(x[1])) / 15
            assert cell * 16 == pytest.approx(base_width / 16)

        # A click on a cell that flips: its pendulum, the flip marked, bobs where
        # Chain.positions puts them.
        flipping = sorted((x, y) for (x, y), v in cells.items() if math.isfinite(v) and v > 1)
        browser.get(f"{base}/#" + urllib.parse.urlencode(VIEW))
        wait_for(browser, "return npendExplore.done()")
        x, y = flipping[len(flipping) // 2]
        px, py = browser.execute_script("return npendExplore.toCanvas(arguments[0], arguments[1])",
                                        x, y)
        canvas = browser.find_element(By.ID, "map")
        ActionChains(browser).move_to_element_with_offset(canvas, px - 256, py - 256).click().perform()
        wait_for(browser, "return npendExplore.trajectory && npendExplore.trajectory.flip !== null")
        trajectory = browser.execute_script(
            "const t = npendExplore.trajectory; return {flip: t.flip, rows: t.rows, "
            "t: Array.from(t.columns.t), phi1: Array.from(t.columns.phi_1), "
            "phi2: Array.from(t.columns.phi_2), p1: Array.from(t.columns.p_1), "
            "p2: Array.from(t.columns.p_2)}")
        assert trajectory["flip"] == cells[(x, y)]
        assert (trajectory["phi1"][0], trajectory["phi2"][0]) == (x, y)  # the cell's own start
        chain = npend.Chain(2)
        transform = browser.execute_script("return npendExplore.pendulumTransform()")
        for row in [0, trajectory["rows"] // 3, trajectory["rows"] - 1]:
            browser.execute_script("npendExplore.setFrame(arguments[0])", row)
            positions = np.asarray(chain.positions([trajectory[k][row]
                                                    for k in ("phi1", "phi2", "p1", "p2")]))
            flipped = trajectory["t"][row] >= trajectory["flip"]
            for bob in range(2):
                bx = transform["cx"] + transform["scale"] * positions[bob, 0]
                by = transform["cy"] + transform["scale"] * positions[bob, 1]
                colour = tuple(pixel(browser, "pendulum", bx, by)[:3])
                assert colour == ((214, 39, 40) if flipped else (33, 145, 140)), (row, bob, colour)
        wait_for(browser, "return document.getElementById('lyapunov').textContent"
                          ".startsWith('maximal')")

        # A parameter changed in the panel goes into the address, which brings it back.
        field = browser.find_element(By.NAME, "t-end")
        field.clear()
        field.send_keys("7")
        browser.find_element(By.ID, "apply").click()
        wait_for(browser, "return npendExplore.done()")
        address = browser.current_url
        assert "t-end=7" in address
        if os.environ.get("NPEND_EXPLORE_SCREENSHOT"):
            browser.save_screenshot(os.environ["NPEND_EXPLORE_SCREENSHOT"])
        browser.get("about:blank")
        browser.get(address)
        wait_for(browser, "return window.npendExplore && npendExplore.done()")
        assert browser.execute_script("return npendExplore.options")["t-end"] == "7"
        assert browser.find_element(By.NAME, "t-end").get_attribute("value") == "7"
