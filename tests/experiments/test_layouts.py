"""Generated layouts (`--layouts generated`): every one a person could arrange, drawn within
the scenario's ranges, the same for the same seed, written as scenarios `run` replays."""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest

from hsr_handover.experiments.intent.trials import make_trials
from hsr_handover.experiments.layouts import NEAR_EDGE, SEATS, generate_layout, seat_for_table
from hsr_handover.experiments.seating import sit_clear
from hsr_handover.interface.object_colors import OBJECT_COLORS
from hsr_handover.scenario import ScenarioError, load_scenario
from hsr_handover.scenario.checks import check_scenario
from hsr_handover.scenario.schema import LayoutsConfig
from hsr_handover.scenario.writing import write_scenario
from hsr_handover.world.person.aiming import arm_points
from hsr_handover.world.person.behavior import OVER_TABLE, rest_posture
from hsr_handover.world.person.body import FOREARM_RADIUS, arm_joint_indices
from hsr_handover.world.station import build_station, initial_overlaps
from tests.paths import SCENARIOS

BASE = SCENARIOS / "intent_reference.yaml"


def _layouts(count: int, seed: int = 3):
    base = load_scenario(BASE)
    rng = np.random.default_rng(seed)
    return base, [generate_layout(base, rng) for _ in range(count)]


def test_generated_layouts_pass_the_scenario_checks_and_stay_in_their_ranges():
    _, layouts = _layouts(60)
    ranges = LayoutsConfig()
    for scenario, drawn in layouts:
        check_scenario(scenario)  # objects on the table, apart, distinct colours, ...
        assert ranges.person_height[0] <= scenario.person.height <= ranges.person_height[1]
        assert ranges.table_height[0] <= scenario.table.height <= ranges.table_height[1]
        assert 3 <= len(scenario.objects) <= 6
        assert len({obj.color for obj in scenario.objects}) == len(scenario.objects)
        assert {obj.color for obj in scenario.objects} <= set(OBJECT_COLORS)
        for a, b in itertools.pairwise(scenario.objects):
            apart = math.dist(a.position, b.position)
            assert ranges.object_spacing[0] - 1e-9 <= apart
            assert abs(b.position[1] - a.position[1]) <= ranges.object_spacing[1] + 1e-9
        facing = math.degrees(scenario.person.yaw - math.pi)
        assert abs(facing) <= 25.0 and drawn["facing_deg"] == pytest.approx(facing)
        # The person across the table, the robot's base before it.
        far_edge = scenario.table.center[0] + scenario.table.size[0] / 2
        assert scenario.person.position[0] >= far_edge + ranges.person_back[0] - 1e-9
        assert scenario.robot.base_pose[0] + 0.218 < NEAR_EDGE - 0.1
    postures = {scenario.person.posture for scenario, _ in layouts}
    arrangements = {drawn["arrangement"] for _, drawn in layouts}
    assert postures == {"seated", "standing"} and arrangements == {"row", "staggered"}
    alongs = [scenario.person.position[1] for scenario, _ in layouts]
    assert min(alongs) < -0.3 and max(alongs) > 0.3  # off the table's axis both ways


def test_a_seated_person_sits_at_a_seat_that_rests_the_forearms_over_the_table():
    """On one dining chair at every table, a short person's elbows were 10-20 cm under a high
    table's top and the resting hands, raised over it, hid the face."""
    _, layouts = _layouts(60)
    seated = [(scenario, drawn) for scenario, drawn in layouts if drawn["posture"] == "seated"]
    assert len(seated) >= 10
    for scenario, drawn in layouts:
        person, top = scenario.person, scenario.table.height
        if drawn["posture"] == "standing":
            assert drawn["seat_height_m"] is None
            continue
        assert SEATS[0] <= person.seat_height <= SEATS[1]
        assert drawn["seat_height_m"] == person.seat_height
        body = person.body()
        rest = rest_posture(body, top)
        np.testing.assert_array_equal(rest, rest_posture(body))  # the armrest rest, not raised
        for arm in ("right", "left"):
            elbow = arm_points(body, arm, rest[arm_joint_indices(arm)])["elbow"]
            assert elbow[2] - FOREARM_RADIUS >= top + OVER_TABLE - 1e-9
    assert seat_for_table(1.50, 0.85) > 0.6 > seat_for_table(1.95, 0.60)


def test_nothing_overlaps_at_the_start_once_the_person_sits_clear():
    _, layouts = _layouts(6, seed=11)
    for scenario, _ in layouts:
        sit_clear(scenario)
        assert initial_overlaps(build_station(scenario)) == []


@pytest.mark.parametrize("yaw", [-0.4, 0.4])
def test_the_robot_moved_and_turned_its_most_toward_a_table_at_hand_height_is_clear(yaw):
    base = load_scenario(BASE)
    base.layouts.base_offset, base.layouts.base_yaw = [0.2, 0.2], [yaw, yaw]
    base.layouts.table_height = [0.66, 0.70]  # the tucked hand's height
    scenario, _ = generate_layout(base, np.random.default_rng(4))
    overlaps = initial_overlaps(build_station(scenario))
    assert [o for o in overlaps if o.key == "robot.base_pose"] == []


def test_the_same_seed_gives_the_same_trials_and_another_seed_others():
    base = load_scenario(BASE)
    first = make_trials(base, 4, 2, seed=5, layouts="generated")
    again = make_trials(base, 4, 2, seed=5, layouts="generated")
    other = make_trials(base, 4, 2, seed=6, layouts="generated")
    as_data = lambda trials: [dataclasses.asdict(t.scenario) for t in trials]  # noqa: E731
    assert as_data(first) == as_data(again) and as_data(first) != as_data(other)
    assert [t.layout for t in first] == [t.layout for t in again]
    # Targets cycle over each trial's own objects, each with its side as the person sees it.
    names = [[obj.name for obj in t.scenario.objects] for t in first[:4]]
    assert [t.target for t in first[:4]] == [n[i % len(n)] for i, n in enumerate(names)]
    assert all(t.position in ("left", "centre", "right") for t in first[:4])
    assert [t.kind for t in first[4:]] == ["gesture", "arm_on_table"]


def test_a_narrowed_range_is_kept_and_one_beyond_the_defaults_is_refused(tmp_path):
    text = BASE.read_text() + "layouts:\n  standing_probability: 1.0\n  table_height: [0.8, 0.82]\n"
    narrowed = tmp_path / "narrow.yaml"
    narrowed.write_text(text)
    base = load_scenario(narrowed)
    rng = np.random.default_rng(0)
    for _ in range(10):
        scenario, _ = generate_layout(base, rng)
        assert scenario.person.posture == "standing"
        assert 0.8 <= scenario.table.height <= 0.82
    wide = tmp_path / "wide.yaml"
    wide.write_text(BASE.read_text() + "layouts:\n  table_height: [0.5, 0.8]\n")
    with pytest.raises(ScenarioError, match=r"layouts.table_height\[0\]: expected a number in"):
        load_scenario(wide)


def test_a_trial_layout_written_out_loads_back_the_same(tmp_path):
    _, [(scenario, _)] = _layouts(1)
    path = tmp_path / "trial.yaml"
    write_scenario(scenario, path, "a generated layout")
    loaded = load_scenario(path)
    loaded.source = scenario.source
    assert dataclasses.asdict(loaded) == dataclasses.asdict(scenario)
    assert path.read_text().startswith("# a generated layout\n")


def test_a_generated_trial_runs_with_its_layout_in_its_row_and_written_beside(tmp_path):
    from hsr_handover.experiments.intent.trial import run_intent_experiment, summarise

    base = load_scenario(BASE)
    experiment = run_intent_experiment(
        base, 1, 0, seed=2, workers=1, layouts="generated", scenario_dir=tmp_path
    )
    (row,) = experiment.rows()
    (trial,) = experiment.trials
    assert row["error"] == ""
    assert row["class_posture"] == trial.scenario.person.posture
    assert row["layout_table_height_m"] == pytest.approx(trial.scenario.table.height)
    written = load_scenario(tmp_path / "trial_000.yaml")
    assert [obj.name for obj in written.objects] == [obj.name for obj in trial.scenario.objects]
    assert written.person.behavior == trial.scenario.person.behavior
    summary = summarise(experiment)
    assert summary["layouts"] == "generated" and summary["trials"] == 1
    (posture,) = summary["by_class"]["posture"].values()
    assert posture["trials"] == 1


def test_an_unknown_layout_source_is_refused_by_name():
    with pytest.raises(ValueError, match="layouts: expected one of"):
        make_trials(load_scenario(BASE), 1, 0, seed=0, layouts="random")
