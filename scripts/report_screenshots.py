#!/usr/bin/env python3
"""Screenshots of the report pages for docs/images/: the run page of the bundled
a_hot_cell race and the sweep pages of examples/sweeps/eco_marathon_grid.yaml (a 2-D
grid) and motorcycle_spread_mc.yaml (a Monte Carlo), in headless Chromium.

    PYTHONPATH=build/python python3 scripts/report_screenshots.py [OUT_DIR]

Needs chromium and chromium-driver (scripts/install-deps.sh) and selenium.
"""
from __future__ import annotations

import os
import sys
import tempfile
import time

import packsim

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MAX_HEIGHT_PX = 3600


def shoot(driver, page: str, png: str) -> None:
    driver.set_window_size(1400, 1000)
    driver.get("file://" + os.path.abspath(page))
    time.sleep(2.0)  # let every figure draw
    h = driver.execute_script("return document.body.scrollHeight")
    driver.set_window_size(1400, min(h + 20, MAX_HEIGHT_PX))
    time.sleep(1.0)
    driver.save_screenshot(png)
    print(png)


def main() -> int:
    from selenium import webdriver
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(REPO, "docs", "images")
    os.makedirs(out, exist_ok=True)
    opts = webdriver.ChromeOptions()
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"):
        opts.add_argument(a)
    driver = webdriver.Chrome(service=webdriver.ChromeService(executable_path="/usr/bin/chromedriver"),
                              options=opts)
    with tempfile.TemporaryDirectory() as tmp:
        try:
            run = os.path.join(tmp, "a_hot_cell.html")
            packsim.report(packsim.run("a_hot_cell"), run)
            shoot(driver, run, os.path.join(out, "report-run.png"))
            for name, png in (("eco_marathon_grid", "report-sweep-grid.png"),
                              ("motorcycle_spread_mc", "report-sweep-mc.png")):
                folder = os.path.join(tmp, name)
                if not packsim.batch(os.path.join(REPO, "examples", "sweeps", f"{name}.yaml"), output_dir=folder).ok:
                    print(f"{name}: a case failed", file=sys.stderr)
                    return 1
                page = os.path.join(tmp, f"{name}.html")
                packsim.report(folder, page)
                shoot(driver, page, os.path.join(out, png))
        finally:
            driver.quit()
    return 0


if __name__ == "__main__":
    sys.exit(main())
