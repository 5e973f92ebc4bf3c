"""explorer.compare.BRDFList: colours, show/hide, solo, replace, remove, limits and errors."""

from __future__ import annotations

import re

import pytest

from explorer.compare import COMPARE_COLOURS, BRDFList
from lighting import BlinnPhong, Lambert, Phong


def _models(count):
    return [Lambert(0.1 + 0.1 * k) for k in range(count)]


def test_the_palette_is_seven_distinct_okabe_ito_colours_without_black():
    assert len(COMPARE_COLOURS) == len(set(COMPARE_COLOURS)) == 7
    assert "#000000" not in COMPARE_COLOURS


def test_added_entries_get_distinct_colours_in_palette_order():
    group = BRDFList()
    entries = [group.add(m, f"m{k}") for k, m in enumerate(_models(7))]
    assert [e.colour for e in entries] == list(COMPARE_COLOURS)
    assert all(e.visible for e in entries)
    assert [e.label for e in group] == [f"m{k}" for k in range(7)]


def test_a_freed_colour_is_the_next_one_given_and_an_explicit_colour_is_kept():
    group = BRDFList(_models(3))
    freed = group.remove(1).colour
    assert freed == COMPARE_COLOURS[1]
    assert group.add(Phong(0.5, 10.0)).colour == freed  # the first colour no entry has
    assert group.add(Phong(0.5, 20.0), colour="#123456").colour == "#123456"
    assert len({e.colour for e in group}) == len(group) == 4


def test_labels_default_to_the_model_summary():
    model = BlinnPhong(0.5, 30.0, normalized=True)
    group = BRDFList([model, (Lambert(0.5), "matte")])
    assert group[0].label == model.summary() and group[1].label == "matte"


def test_hidden_entries_keep_place_and_colour_and_solo_wins_over_hidden():
    group = BRDFList([(m, f"m{k}") for k, m in enumerate(_models(4))])
    colours = [e.colour for e in group]
    group.set_visible(1, False)
    group.set_visible(3, False)
    assert [e.label for e in group.shown()] == ["m0", "m2"]
    assert [e.colour for e in group] == colours
    group.set_solo(3)
    assert [e.label for e in group.shown()] == ["m3"]  # solo shows a hidden entry alone
    group.set_solo(-4)  # negative indices count from the end, as for a list
    assert group.solo == 0 and [e.label for e in group.shown()] == ["m0"]
    group.set_solo(None)
    assert [e.label for e in group.shown()] == ["m0", "m2"]  # back to the check boxes
    assert repr(group) == "BRDFList([m0, m1 (hidden), m2, m3 (hidden)])"


@pytest.mark.parametrize(
    ("solo", "removed", "solo_after", "shown_after"),
    [
        (2, 0, 1, ["m2"]),  # an earlier entry goes: solo follows its entry to the new index
        (2, 3, 2, ["m2"]),  # a later entry goes: solo stays
        (2, 2, None, ["m0", "m1", "m3"]),  # the solo entry goes: solo is cleared
    ],
)
def test_remove_keeps_solo_on_the_same_entry(solo, removed, solo_after, shown_after):
    group = BRDFList([(m, f"m{k}") for k, m in enumerate(_models(4))])
    group.set_solo(solo)
    gone = group.remove(removed)
    assert gone.label == f"m{removed}"
    assert group.solo == solo_after
    assert [e.label for e in group.shown()] == shown_after


def test_replace_keeps_colour_visibility_and_label_unless_given():
    group = BRDFList([(Lambert(0.5), "a"), (Phong(0.5, 10.0), "b")])
    group.set_visible(1, False)
    before = group[1].colour
    new = Phong(0.5, 40.0)
    entry = group.replace(1, new)
    assert entry is group[1] and entry.brdf is new
    assert (entry.colour, entry.visible, entry.label) == (before, False, "b")
    assert group.replace(1, Lambert(0.2), "c").label == "c"


def test_max_entries_is_enforced_with_a_named_error():
    group = BRDFList(_models(2), max_entries=2)
    with pytest.raises(ValueError, match=re.escape("the comparison holds at most 2 BRDFs; remove one first")):
        group.add(Lambert(0.3))
    assert len(group) == 2
    group.remove(0)
    group.add(Lambert(0.3))  # room again
    assert len(group) == 2
    with pytest.raises(ValueError, match=re.escape("max_entries must be an integer >= 1; got 0")):
        BRDFList(max_entries=0)
    with pytest.raises(ValueError, match="max_entries must be an integer >= 1; got 2.5"):
        BRDFList(max_entries=2.5)


def test_default_limit_is_eight():
    group = BRDFList(_models(8))
    with pytest.raises(ValueError, match="at most 8"):
        group.add(Lambert(0.9))


@pytest.mark.parametrize("bad", [0.5, "lambert", None, (Lambert(0.5),)])
def test_only_models_are_taken(bad):
    group = BRDFList([Lambert(0.5)])
    with pytest.raises(TypeError, match="brdf must be a BRDF model; got "):
        group.add(bad)
    with pytest.raises(TypeError, match="brdf must be a BRDF model; got "):
        group.replace(0, bad)
    assert len(group) == 1 and isinstance(group[0].brdf, Lambert)


@pytest.mark.parametrize("index", [3, -4, True, 1.0, "0", None])
def test_bad_indices_name_the_allowed_range(index):
    group = BRDFList(_models(3))
    for call in (group.remove, group.set_visible, group.set_solo, group.__getitem__):
        if call == group.set_solo and index is None:
            continue  # None clears solo
        with pytest.raises(IndexError, match=re.escape("entry must be an index in [0, 3); got ")):
            call(index)
    assert len(group) == 3 and group.solo is None
