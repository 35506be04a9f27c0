"""The report in a real headless Chromium: the page loads from the file alone, the graph
library drew every policy node, clicking a node on the canvas fills its detail panel,
and a screenshot is taken (tests/view/screenshots/ keeps the last ones to look at)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from stampc.view import view_run

from .browser import load_report, start_chromium, stop

SHOTS = Path(__file__).parent / "screenshots"


@pytest.fixture(scope="module")
def chrome():
    browser = start_chromium()
    yield browser
    stop(browser)


def click_node(chrome, uid: int) -> None:
    """A real mouse click on the node's position on the canvas."""
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By

    # the whole canvas in the viewport: Selenium offsets are from its visible part's centre
    chrome.execute_script("document.getElementById('graph').scrollIntoView({block: 'start'});"
                          "stampcReport.network.focus(arguments[0], {scale: 1, animation: false});"
                          "stampcReport.network.redraw();", uid)
    x, y = chrome.execute_script("""
        const net = stampcReport.network, p = net.canvasToDOM(net.getPosition(arguments[0]));
        return [p.x, p.y];""", uid)
    graph = chrome.find_element(By.ID, "graph")
    size = graph.size
    ActionChains(chrome).move_to_element_with_offset(
        graph, int(x - size["width"] / 2), int(y - size["height"] / 2)).click().perform()


def check_report(chrome, run: Path, name: str) -> dict:
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import WebDriverWait

    policy = json.loads((run / "policy.json").read_text())
    report = view_run(run)
    load_report(chrome, report)
    assert chrome.get_log("browser") == []  # no script error, nothing failed to load
    nodes = len(policy["nodes"])
    assert chrome.execute_script("return stampcReport.network.body.nodeIndices.length") == nodes
    chrome.find_element(By.CSS_SELECTOR, "#all-nodes summary").click()  # built when opened
    rows = WebDriverWait(chrome, 10).until(
        lambda d: d.find_elements(By.CSS_SELECTOR, "#node-table tbody tr"))
    assert len(rows) == nodes
    assert f"({nodes} nodes" in chrome.find_element(By.ID, "node-count").text
    # states travel as differences from a parent's: every one is rebuilt exactly
    rebuilt = chrome.execute_script(
        "return stampcReport.network.body.nodeIndices.map(id => [id, stampcReport.stateFacts(id)])")
    assert {uid: sorted(facts) for uid, facts in rebuilt} == \
        {n["id"]: sorted(n["state"]) for n in policy["nodes"]}
    return policy


def check_detail(chrome, node: dict) -> str:
    from selenium.webdriver.common.by import By

    click_node(chrome, node["id"])
    panel = chrome.find_element(By.ID, "detail")
    assert panel.get_attribute("data-node") == str(node["id"])
    text = panel.text
    assert f"node {node['id']}" in text and node["action"] in text
    for fact in node["state"][:3]:
        assert fact in text
    return text


def screenshot(chrome, name: str) -> Path:
    SHOTS.mkdir(exist_ok=True)
    path = SHOTS / f"{name}.png"
    assert chrome.save_screenshot(str(path))
    assert path.stat().st_size > 20_000  # a drawn page, not a blank one
    return path


def test_plane2d_report(chrome, shelf_run):
    policy = check_report(chrome, shelf_run, "shelf2d")
    node = next(n for n in policy["nodes"] if n.get("sigma") and n["depth"] > 0)
    text = check_detail(chrome, node)
    assert "refined" in text and "trajectory:" in text  # status and concrete values
    for symbol in node["sigma"]:
        assert symbol in text
    history = json.loads((shelf_run / "prg.json").read_text())
    from selenium.webdriver.common.by import By
    rows = chrome.find_elements(By.CSS_SELECTOR, "#revisions tr[data-prg]")
    assert len(rows) == len(history["revisions"])
    # a row of the node table selects its node
    row = chrome.find_element(By.CSS_SELECTOR, f"#node-table tr[data-node='{policy['root']}']")
    row.click()
    assert chrome.find_element(By.ID, "detail").get_attribute("data-node") == str(policy["root"])
    click_node(chrome, node["id"])
    screenshot(chrome, "shelf2d")


def test_pybullet_report_with_frames_and_execution(chrome, domino_run):
    from selenium.webdriver.common.by import By

    policy = check_report(chrome, domino_run, "domino")
    root = next(n for n in policy["nodes"] if n["id"] == policy["root"])
    text = check_detail(chrome, root)
    for outcome in root["outcomes"][:3]:
        assert f"node {outcome['child']}" in text  # outcome links to the children
    # the grasp chosen at the root, as a value line in the panel
    assert any(k.startswith("g_") for k in root["sigma"]) and '"kind": "top"' in text
    frame = chrome.find_element(By.ID, "frame-img")
    assert chrome.execute_script("return arguments[0].naturalWidth", frame) > 0
    assert "3 runs: 3 successes" in chrome.find_element(By.ID, "execution-body").text
    screenshot(chrome, "domino")


def test_a_leaf_click_shows_its_status(chrome, domino_run):
    from selenium.webdriver.common.by import By

    policy = json.loads((domino_run / "policy.json").read_text())
    load_report(chrome, domino_run / "report.html")
    leaf = next(n for n in policy["nodes"] if n["leaf"] == "goal")
    click_node(chrome, leaf["id"])
    panel = chrome.find_element(By.ID, "detail")
    assert panel.get_attribute("data-node") == str(leaf["id"])
    assert "goal" in panel.text and "Goal facts" in panel.text


def test_a_5000_node_policy_loads_and_every_node_is_drawn(chrome, tmp_path):
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "bench_view", Path(__file__).resolve().parents[2] / "bench" / "view.py")
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    run = bench.synthetic_run(tmp_path / "big", 5000)
    policy = check_report(chrome, run, "synthetic")
    node = next(n for n in policy["nodes"] if n.get("sigma") and n["depth"] > 4)
    check_detail(chrome, node)
    screenshot(chrome, "synthetic5000")
