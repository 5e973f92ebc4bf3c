"""The command line's near-plane rule over every shipped scene, each explained in words (slow set; fast:
test_cli_errors.py)."""

import re

import pytest
from test_cli_errors import run

from lighting.scene import list_examples

pytestmark = pytest.mark.slow  # every shipped scene loaded and explained


# ----------------------------------------------------------------------------- sizes named by their option or key
def test_the_near_plane_rule_refuses_no_shipped_scene_and_explain_counts_in_words(capsys):
    # The near-plane rule refuses nothing the shipped scenes hold.
    for name in list_examples():
        status, out, err = run(["render", name, "--explain"], capsys)
        assert status == 0 and err == "", (name, err)
        assert re.match(r"\d+ objects?, \d+ lights?, \d+x\d+ pixels\.$", out.splitlines()[0]), out
