"""The circle and rectangle fits of an object's visible sides (layer 1)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hsr_handover.robot.perception.outline_fit import fit_circle, fit_rectangle


def _arc(center, radius, start_deg, end_deg, n=300):
    angles = np.radians(np.linspace(start_deg, end_deg, n))
    return np.asarray(center) + radius * np.column_stack([np.cos(angles), np.sin(angles)])


def _two_faces(center, half_sides, yaw, n=150):
    """The two faces of a rectangle (`half_sides` along and across, turned `yaw`) that meet at
    its corner nearest the origin's side."""
    a, b = half_sides
    along = np.column_stack([np.linspace(-a, a, n), np.full(n, -b)])
    across = np.column_stack([np.full(n, -a), np.linspace(-b, b, n)])
    turn = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])
    return np.asarray(center) + np.vstack([along, across]) @ turn.T


def test_a_third_of_a_round_gives_its_whole_circle():
    fit = fit_circle(_arc((0.9, -0.2), 0.035, 150.0, 270.0))
    np.testing.assert_allclose(fit.center, [0.9, -0.2], atol=1e-9)
    assert fit.radius == pytest.approx(0.035, abs=1e-9)
    assert fit.deviation < 1e-9


def test_the_circle_is_not_moved_by_a_few_stray_points():
    arc = _arc((0.9, -0.2), 0.035, 120.0, 260.0)
    stray = np.array([[0.95, -0.1], [0.8, -0.3], [0.99, -0.2]])
    fit = fit_circle(np.vstack([arc, stray]))
    assert fit.deviation < 1e-3  # the median: the three stray points do not count
    assert fit.radius == pytest.approx(0.035, abs=5e-3)


def test_a_rectangles_two_faces_give_its_orientation_and_lie_on_its_sides():
    fit = fit_rectangle(_two_faces((0.8, 0.1), (0.04, 0.03), math.radians(30.0)))
    assert math.sin(2 * (fit.yaw - math.radians(30.0))) == pytest.approx(0.0, abs=0.04)
    assert fit.deviation < 1e-3


def test_an_arc_follows_a_circle_closer_than_any_rectangle_and_faces_the_other_way():
    arc = _arc((0.9, -0.2), 0.035, 120.0, 260.0)
    faces = _two_faces((0.9, -0.2), (0.035, 0.035), 0.7)
    assert fit_circle(arc).deviation < fit_rectangle(arc).deviation / 10
    assert fit_rectangle(faces).deviation < fit_circle(faces).deviation / 10
