"""Criteria sets: the registry reproduces the published N50s and rejects bad requests."""

import math

import pytest

import targetacq as ta
from targetacq.acquisition.criteria import CRITERIA, get_criterion


def test_johnson_table_3_2_averages():
    johnson = CRITERIA["johnson"]
    assert [johnson.n50(t) for t in ta.TASKS] == [1.0, 1.4, 4.0, 6.4]


@pytest.mark.parametrize(
    ("name", "values"),
    [  # Table 3.1, Sonesson (2004) p. 18
        ("johnson-truck", (0.90, 1.25, 4.5, 8.0)),
        ("johnson-m48-tank", (0.75, 1.2, 3.5, 7.0)),
        ("johnson-stalin-tank", (0.75, 1.2, 3.3, 6.0)),
        ("johnson-centurion-tank", (0.75, 1.2, 3.5, 6.0)),
        ("johnson-half-track", (1.0, 1.5, 4.0, 5.0)),
        ("johnson-jeep", (1.2, 1.5, 4.5, 5.5)),
        ("johnson-command-car", (1.2, 1.5, 4.5, 5.5)),
        ("johnson-soldier-standing", (1.5, 1.8, 3.8, 8.0)),
        ("johnson-105-howitzer", (1.0, 1.5, 4.8, 6.0)),
    ],
)
def test_one_set_per_table_3_1_row_with_orientation(name, values):
    assert tuple(CRITERIA[name].n50(t) for t in ta.TASKS) == values


def test_pixel_rules_are_half_the_pixels_in_cycles():
    assert [
        CRITERIA["pixels-1.5-6-12"].n50(t) for t in ("detection", "recognition", "identification")
    ] == [0.75, 3.0, 6.0]
    assert [
        CRITERIA["pixels-2-8-12.8"].n50(t) for t in ("detection", "recognition", "identification")
    ] == [1.0, 4.0, 6.4]
    assert [
        CRITERIA["stanag-i2"].n50(t) for t in ("detection", "recognition", "identification")
    ] == [1.0, 3.0, 6.0]


def test_c2nveo_criterion_is_the_geometric_mean_of_the_50_percent_row():
    c = CRITERIA["c2nveo"]  # Table 3.3: 0.5-1, 3-4, 6-8
    assert c.n50("detection") == pytest.approx(math.sqrt(0.5 * 1))
    assert c.n50("recognition") == pytest.approx(math.sqrt(3 * 4))
    assert c.n50("identification") == pytest.approx(math.sqrt(6 * 8))


def test_en62676_4_thresholds_give_no_probability():
    c = CRITERIA["en62676-4"]
    assert [c.threshold(t) for t in c.tasks] == [12.5, 25, 62.5, 125, 250, 1000]
    with pytest.raises(ValueError, match="pixel-density thresholds, not probabilities"):
        ta.probability(2.0, "detection", criterion="en62676-4")


def test_user_defined_mapping():
    c = get_criterion({"detection": 0.8, "recognition": 3.0, "identification": 6.0})
    assert c.n50("recognition") == 3.0
    assert ta.probability(3.0, "recognition", criterion={"recognition": 3.0}) == pytest.approx(0.5)


@pytest.mark.parametrize(
    ("criterion", "error", "match"),
    [
        (
            "johnsen",
            ValueError,
            r"unknown criterion 'johnsen' \(did you mean 'johnson'\?\); valid: johnson, ",
        ),
        ({"detect": 1.0}, ValueError, "unknown task"),
        ({"detection": -1.0}, ValueError, "must be a finite number > 0"),
        ({"detection": math.nan}, ValueError, "must be a finite number > 0"),
        (3.0, TypeError, "criterion must be"),
    ],
)
def test_bad_criteria(criterion, error, match):
    with pytest.raises(error, match=match):
        get_criterion(criterion)


def test_missing_task_names_the_tasks_there_are():
    with pytest.raises(ValueError, match="has no task 'orientation'; its tasks: detection"):
        ta.probability(1.0, "orientation", criterion="stanag-i2")
