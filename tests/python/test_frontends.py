"""The three front-ends accept and refuse the same values: the Python module's half. Every case
of tests/frontend/cases.json is given as keywords, its view options to hsr.view() and the rest
to hsr.render(); a case accepted renders, a refused one raises hsr.Error saying what the case
says ({name} spelled as Python spells it: the name itself). The command line
(tests/cli/frontends_test.cpp) and the web page's module (web/test/node_test.mjs) run the same
cases."""
import json
import pathlib
import re

import pytest

import hsr

CASES = json.loads((pathlib.Path(__file__).parents[1] / "frontend" / "cases.json").read_text())["cases"]
VIEW = {o["name"] for o in hsr.options() if o["view"]}


def spelled(says):
    return re.sub(r"\{([a-z_]+)\}", r"\1", says)


@pytest.fixture(scope="module")
def demo():
    return hsr.Scene.load("demo")


@pytest.mark.parametrize("case", [c for c in CASES if "python" in c.get("only", ["python"])],
                         ids=lambda c: json.dumps(c["options"]))
def test_python_accepts_and_refuses_as_the_cases_say(demo, case):
    view = {"size": (64, 48)}
    view.update({k: v for k, v in case["options"].items() if k in VIEW})
    options = {k: v for k, v in case["options"].items() if k not in VIEW}

    def run():
        camera = hsr.view(demo, **view)
        return hsr.render(demo, camera, **options)

    if "says" not in case:
        frame = run()
        assert frame.ids.shape == (view["size"][1], view["size"][0])
    else:
        with pytest.raises(hsr.Error) as refused:
            run()
        assert spelled(case["says"]) in str(refused.value)


def test_options_lists_the_table_with_the_command_lines_spelling():
    by_name = {o["name"]: o for o in hsr.options()}
    assert by_name["depth_test"]["cli"] == "--no-depth-test"
    assert by_name["clear_depth"]["range"] == (0.0, 1.0)
    assert by_name["samples"]["needs"] == "antialiasing"
    assert "pose" not in by_name  # a file the command line reads; Python has Camera.set_pose


def test_view_and_render_options_go_to_their_own_call(demo):
    with pytest.raises(hsr.Error, match="eye sets the camera: give it to hsr.view"):
        hsr.render(demo, hsr.view(demo, size=(8, 6)), eye=(1, 2, 3))
    with pytest.raises(hsr.Error, match="cull is a render option"):
        hsr.view(demo, cull="back")


def test_view_is_the_command_lines_camera(demo, cli, tmp_path):
    stats = tmp_path / "stats.json"
    import subprocess
    subprocess.run([cli, "render", "demo", "--size", "40x30", "--eye", "3,2,4", "--fov", "30",
                    "--output", "none", "--stats", str(stats), "-q"], check=True)
    theirs = json.loads(stats.read_text())["camera"]
    ours = json.loads(hsr.view(demo, size=(40, 30), eye=(3, 2, 4), fov=30).to_json())
    assert ours == theirs
