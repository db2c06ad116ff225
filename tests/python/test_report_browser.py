"""The report pages in a real browser: Debian's headless Chromium driven by Selenium
(chromium-driver). Every figure renders, the time cursor follows the mouse in every
panel, a legend click hides a trace and an event mark, the events filter filters, and
the console shows no error. Skips only when Chromium or its driver is not installed
(scripts/install-deps.sh installs both)."""
from __future__ import annotations

import shutil

import pytest

import packsim

pytest.importorskip("plotly")
webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed (pip install selenium)")

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
DRIVER = shutil.which("chromedriver")
pytestmark = pytest.mark.skipif(CHROMIUM is None or DRIVER is None,
                                reason="Chromium or chromium-driver is not installed (apt-get install chromium "
                                       "chromium-driver; scripts/install-deps.sh does)")


@pytest.fixture(scope="module")
def browser():
    from selenium.webdriver.chrome.service import Service
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1400,1200"):
        opts.add_argument(a)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    d = webdriver.Chrome(service=Service(executable_path=DRIVER), options=opts)
    d.set_script_timeout(20)
    yield d
    d.quit()


def _open(browser, path) -> None:
    browser.get(path.as_uri())
    browser.execute_async_script("""
      var done = arguments[arguments.length - 1];
      var gds = Array.from(document.querySelectorAll('.packsim-figure'));
      Promise.all(gds.map(function(gd){ return new Promise(function(ok){
        (function wait(){ if (gd._fullLayout && gd.querySelector('.main-svg')) ok(); else setTimeout(wait, 50); })();
      }); })).then(function(){ done(true); });
    """)


def _errors(browser) -> list[str]:
    return [e["message"] for e in browser.get_log("browser") if e["level"] == "SEVERE"]


@pytest.fixture(scope="module")
def run_page(tmp_path_factory):
    d = tmp_path_factory.mktemp("browser")
    r = packsim.run("a_hot_cell")
    packsim.report(r, d / "run.html")
    return d / "run.html", r


def test_run_page_renders_with_cursor_toggles_and_filter(browser, run_page):
    page, r = run_page
    _open(browser, page)
    info = browser.execute_script("""
      var gd = document.getElementById('run-figure');
      return {n: gd.data.length, traces: gd.querySelectorAll('.trace').length,
              heatmaps: gd.querySelectorAll('.hm image, .heatmaplayer image').length,
              panels: Object.keys(gd._fullLayout).filter(function(k){ return /^yaxis\\d*$/.test(k); }).length};
    """)
    assert info["n"] > 10 and info["traces"] > 10 and info["panels"] >= 8
    assert info["heatmaps"] == 2  # both deviation heat-maps drew their image

    # the cursor: the mouse over the voltage panel moves the one line that crosses every
    # panel to the time under it
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    drag = browser.find_element(By.CSS_SELECTOR, "#run-figure .draglayer .xy3 .nsewdrag")
    ActionChains(browser).move_to_element_with_offset(drag, 100, 0).perform()
    x = browser.execute_async_script("""
      var done = arguments[arguments.length - 1], gd = document.getElementById('run-figure');
      setTimeout(function(){
        var s = gd.layout.shapes.find(function(s){ return s.name === 'cursor'; }), xa = gd._fullLayout.xaxis;
        done([s.visible, s.x0, s.x1, s.yref, s.y0, s.y1, xa.p2l(xa._length / 2 + 100), xa.range[1] - xa.range[0]]);
      }, 500);
    """)
    visible, x0, x1, yref, y0, y1, under, span = x
    assert visible is True and x0 == x1 and (yref, y0, y1) == ("paper", 0, 1)
    assert abs(x0 - under) < 0.01 * span  # the nearest sample to the mouse

    # a legend click hides a trace; the event kind's click hides its marks
    for name in ("truth hottest cell", "event: fault latched"):
        toggle = browser.execute_script("""
          var items = Array.from(document.querySelectorAll('#run-figure .traces'));
          var it = items.find(function(t){ var x = t.querySelector('text'); return x && x.textContent === arguments[0]; });
          return it.querySelector('rect[class$=toggle]');
        """.replace("arguments[0]", repr(name)))
        # apart by more than Plotly's double-click delay (300 ms), or the second click is a double-click
        ActionChains(browser).move_to_element(toggle).click().pause(0.6).perform()
    traces, marks = browser.execute_async_script("""
      var done = arguments[arguments.length - 1], gd = document.getElementById('run-figure');
      setTimeout(function(){
        var tr = gd.data.filter(function(t){ return t.name === 'truth hottest cell'; }).map(function(t){ return t.visible; });
        var ev = gd.layout.shapes.filter(function(s){ return s.legendgroup === 'event fault_latched'; })
                   .concat(gd.data.filter(function(t){ return t.legendgroup === 'event fault_latched'; }))
                   .map(function(s){ return s.visible; });
        done([tr, ev]);
      }, 800);
    """)
    assert traces and all(v == "legendonly" for v in traces)
    assert len(marks) == 3 and all(v == "legendonly" for v in marks)  # two lines and their diamonds

    # the events filter: only the rows whose kind is chosen stay
    shown = browser.execute_script("""
      var k = document.getElementById('event-kind'); k.value = 'fault_latched';
      k.dispatchEvent(new Event('change'));
      return [Array.from(document.querySelectorAll('#events tbody tr')).filter(function(r){
                return r.style.display !== 'none'; }).map(function(r){ return r.cells[1].textContent; }),
              document.getElementById('event-count').textContent];
    """)
    assert shown[0] == ["fault_latched"] * sum(e["kind"] == "fault_latched" for e in r.events)
    assert shown[1] == f"{len(shown[0])} of {len(r.events)} events"
    assert _errors(browser) == []


def test_sweep_page_renders_every_figure(browser, tmp_path):
    sweep = {"base": packsim.bundled_scenarios("bench_6s_ncr18650_2C.yaml")[0], "output_dir": str(tmp_path / "s"),
             "grid": {"pack.cell.capacity_Ah": [2.8, 3.2], "ambient.temp_C": [10, 40]}}
    assert packsim.batch(sweep).ok
    page = tmp_path / "sweep.html"
    packsim.report(tmp_path / "s", page)
    _open(browser, page)
    counts = browser.execute_script("""
      return Array.from(document.querySelectorAll('.packsim-figure')).map(function(gd){
        return gd.querySelectorAll('.hm image, .heatmaplayer image').length; });
    """)
    assert len(counts) > 5 and all(c == 1 for c in counts)  # one drawn heat-map per output
    order = browser.execute_script("""
      var th = document.querySelectorAll('#cases th')[2]; th.click();
      return Array.from(document.querySelectorAll('#cases tbody tr')).map(function(r){
        return parseFloat(r.cells[2].textContent); });
    """)
    assert order == sorted(order)  # a click sorts by ambient temperature
    assert _errors(browser) == []


def test_monte_carlo_page_menu_picks_the_random_input(browser, tmp_path):
    # bench_6s draws capacity and resistance spreads: a scatter per output, its menu one entry per random input
    sweep = {"base": packsim.bundled_scenarios("bench_6s_ncr18650_2C.yaml")[0], "output_dir": str(tmp_path / "mc"),
             "grid": {"run.duration_s": [600]}, "monte_carlo": {"samples": 4, "master_seed": 2}}
    assert packsim.batch(sweep).ok
    page = tmp_path / "mc.html"
    packsim.report(tmp_path / "mc", page)
    _open(browser, page)
    assert browser.find_element("id", "sensitivity")
    picked = browser.execute_async_script("""
      var done = arguments[arguments.length - 1];
      function guard(f){ return function(){ try { f(); } catch (e) { done('error: ' + e); } }; }
      var gd = Array.from(document.querySelectorAll('.packsim-figure')).find(function(g){
        return g.layout.updatemenus && g.layout.updatemenus.length; });
      var before = gd.data.map(function(t){ return t.visible; });
      guard(function(){
        gd.querySelector('.updatemenu-header').dispatchEvent(new MouseEvent('click', {bubbles: true}));
      })();
      setTimeout(guard(function(){
        var buttons = gd.querySelectorAll('.updatemenu-dropdown-button');
        buttons[1].dispatchEvent(new MouseEvent('click', {bubbles: true}));
        setTimeout(guard(function(){
          done([before, gd.data.map(function(t){ return t.visible; }), gd.data[1].name,
                gd.layout.xaxis.title.text, buttons.length]);
        }), 300);
      }), 300);
    """)
    assert not isinstance(picked, str), picked
    before, after, name, x_title, n_buttons = picked
    assert before[0] is True and before.count(True) == 1
    assert after[1] is True and after.count(True) == 1 and n_buttons == len(after)
    assert x_title == name  # the x axis names the input now shown
    assert _errors(browser) == []
