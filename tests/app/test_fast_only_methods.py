"""Queries that compute in float64 only (sampled studies) accept method = "fast" and
refuse the other tiers with the field, the reason and where the precise or certified
answer is -- never a float answer under a certified name."""

import pytest

from distkin.app.scene import loads_scene
from distkin.errors import InputError

SCENE = """
[mechanism]
kind = "rss"
preset = "octo"
[[query]]
type = "{type}"
{extra}
"""


@pytest.mark.parametrize("qtype, where", [("performance", "certify_workspace"),
                                          ("design_sweep", "certify_workspace"),
                                          ("table5", "forward_kinematics")])
def test_fast_only_queries(qtype, where):
    loads_scene(SCENE.format(type=qtype, extra='method = "fast"'))
    for tier in ("precise", "certified"):
        with pytest.raises(InputError) as err:
            loads_scene(SCENE.format(type=qtype, extra=f'method = "{tier}"'))
        msg = str(err.value)
        assert "query[0].method" in msg and f"got '{tier}'" in msg
        assert "float64" in msg and where in msg
    with pytest.raises(InputError, match="'fast', 'precise', 'certified'"):
        loads_scene(SCENE.format(type=qtype, extra='method = "exact"'))
