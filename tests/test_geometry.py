"""Polygon kernels: exact cases and properties (symmetry, bounds, rigid-motion invariance, continuity)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dem_core import geometry
from dem_core.engine.geometry import GeometryError, as_convex_ccw, contact_geometry, overlap_area, rectangle, transform


def test_rectangle_mass_properties_are_exact():
    props = geometry.polygon_properties(rectangle(2.0, 3.0, 1.0, -1.0))
    assert props.area == pytest.approx(6.0, rel=1e-14)
    np.testing.assert_allclose(props.centroid, [2.0, 0.5], rtol=1e-14)
    # polar moment of a w x h rectangle about its centroid: A (w^2 + h^2) / 12
    assert props.polar_moment == pytest.approx(6.0 * (4.0 + 9.0) / 12.0, rel=1e-13)


def test_overlap_of_offset_squares_is_exact():
    a = rectangle(1.0, 1.0)
    b = rectangle(1.0, 1.0, 0.25, 0.5)
    contact = contact_geometry(a, b)
    assert contact.area == pytest.approx(0.75 * 0.5, rel=1e-13)
    np.testing.assert_allclose(contact.centroid, [0.625, 0.75], rtol=1e-13)


def test_thin_face_overlap_has_face_tangent_and_normal_pointing_from_first_to_second():
    base = rectangle(4.0, 1.0, -2.0, -1.0)
    block = rectangle(1.0, 2.0, -0.5, -1e-4)
    contact = contact_geometry(base, block)
    assert contact.area == pytest.approx(1e-4, rel=1e-9)
    np.testing.assert_allclose(np.abs(contact.tangent), [1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(contact.normal, [0.0, 1.0], atol=1e-12)
    assert contact.length == pytest.approx(1.0, rel=1e-12)
    flipped = contact_geometry(block, base)
    np.testing.assert_allclose(flipped.normal, [0.0, -1.0], atol=1e-12)


def test_disjoint_and_touching_polygons_have_no_overlap():
    assert contact_geometry(rectangle(1, 1), rectangle(1, 1, 2.0, 0.0)) is None
    assert overlap_area(rectangle(1, 1), rectangle(1, 1, 1.0, 0.0)) == 0.0


def test_triangle_corner_overlap_area():
    # a unit square tilted 45 degrees pushed 0.1 m into a half-plane: triangle of height 0.1, base 0.2
    diamond = transform(rectangle(1.0, 1.0, -0.5, -0.5), np.pi / 4, (0.0, np.sqrt(0.5) - 0.1))
    ground = rectangle(10.0, 1.0, -5.0, -1.0)
    assert overlap_area(ground, diamond) == pytest.approx(0.1 * 0.2 / 2.0, rel=1e-12)


@pytest.mark.parametrize("vertices, message", [
    ([[0, 0], [1, 0]], "at least 3 vertices"),
    ([[0, 0], [1, 0], [2, 0]], "degenerate"),
    ([[0, 0], [2, 0], [1, 0.2], [2, 2], [0, 2]], "not convex"),
    ([[0, 0], [1, 0], [1, 0], [0, 1]], "repeated vertices"),
    ([[0, 0], [1, np.nan], [0, 1]], "not all finite"),
])
def test_bad_polygons_are_rejected_with_a_reason(vertices, message):
    with pytest.raises(GeometryError, match=message):
        as_convex_ccw(vertices, name="drum7")
    with pytest.raises(GeometryError, match="drum7"):
        as_convex_ccw(vertices, name="drum7")


def test_clockwise_input_is_reversed():
    v = as_convex_ccw(rectangle(1.0, 2.0)[::-1])
    assert geometry.polygon_properties(v).area > 0


coordinate = st.floats(-2.0, 2.0, allow_nan=False)


@st.composite
def convex_polygons(draw):
    """Random convex polygons: a rectangle or a regular-ish polygon, rotated and shifted."""
    kind = draw(st.sampled_from(["rect", "ngon"]))
    if kind == "rect":
        v = rectangle(draw(st.floats(0.05, 2.0)), draw(st.floats(0.05, 2.0)))
        v = v - v.mean(axis=0)
    else:
        n = draw(st.integers(3, 8))
        radius = draw(st.floats(0.1, 1.5))
        angles = np.sort(np.array(draw(st.lists(st.floats(0, 2 * np.pi), min_size=n, max_size=n, unique=True))))
        if np.min(np.diff(np.concatenate([angles, [angles[0] + 2 * np.pi]]))) < 0.05:
            angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
        v = radius * np.column_stack([np.cos(angles), np.sin(angles)])
    return transform(v, draw(st.floats(0, 2 * np.pi)), (draw(coordinate), draw(coordinate)))


@settings(max_examples=200, deadline=None)
@given(convex_polygons(), convex_polygons())
def test_overlap_area_is_symmetric_and_bounded(p, q):
    a_pq = overlap_area(p, q)
    a_qp = overlap_area(q, p)
    size = max(geometry.polygon_properties(p).area, geometry.polygon_properties(q).area)
    assert a_pq == pytest.approx(a_qp, rel=1e-9, abs=1e-12 * size)
    assert a_pq <= geometry.polygon_properties(p).area * (1 + 1e-12) + 1e-15
    assert a_pq <= geometry.polygon_properties(q).area * (1 + 1e-12) + 1e-15
    assert a_pq >= 0.0


@settings(max_examples=200, deadline=None)
@given(convex_polygons(), convex_polygons(), st.floats(0, 2 * np.pi), coordinate, coordinate)
def test_contact_geometry_is_invariant_under_rigid_motion(p, q, angle, dx, dy):
    before = contact_geometry(p, q)
    after = contact_geometry(transform(p, angle, (dx, dy)), transform(q, angle, (dx, dy)))
    if before is None or before.area < 1e-9:
        return
    assert after.area == pytest.approx(before.area, rel=1e-8)
    np.testing.assert_allclose(after.centroid, transform(before.centroid[None, :], angle, (dx, dy))[0], atol=1e-9)
    rotated_normal = transform(before.normal[None, :], angle)[0]
    # the frame is defined when the overlap is elongated (a principal axis exists) and its centroid lies
    # off p's centre (the side of p it is on orients n); concentric overlaps are ambiguous by nature
    offset = before.normal @ (before.centroid - geometry.polygon_properties(p).centroid)
    if before.length ** 2 > 4.0 * before.area and offset > 1e-6:
        np.testing.assert_allclose(after.normal, rotated_normal, atol=1e-6)


def test_tangent_does_not_jump_when_the_overlap_turns_from_triangle_to_quadrilateral():
    """A block rocking back onto its face: the overlap goes from a triangle to a quadrilateral."""
    ground = rectangle(10.0, 1.0, -5.0, -1.0)
    block = rectangle(1.0, 2.0, -0.5, 0.0)
    depth = 1e-3
    previous = None
    counts = set()
    for theta in np.linspace(0.01, 0.0, 401):
        pivot = np.array([-0.5, 0.0])
        v = transform(block - pivot, theta, pivot) - [0.0, depth]
        contact = contact_geometry(ground, v)
        counts.add(_vertex_count(ground, v))
        if previous is not None:
            assert np.arccos(np.clip(abs(contact.tangent @ previous), -1, 1)) < 1e-3
        previous = contact.tangent
    assert {3, 4} <= counts  # the sweep did cross the triangle/quadrilateral change


def _vertex_count(p, q):
    from dem_core.engine import _polygon

    cap = len(p) + len(q) + 2
    out = [np.empty(cap), np.empty(cap)]
    return _polygon.clip_convex(p[:, 0].copy(), p[:, 1].copy(), 0, len(p), q[:, 0].copy(), q[:, 1].copy(), 0,
                                 len(q), out[0], out[1], np.empty((2, 2, cap)))


def test_the_quick_sine_and_cosine_are_the_librarys_to_a_unit_in_the_last_place():
    """dem_core/engine/_angles.py: across the series' range (and just beyond it, where the library answers) the
    series give math.sin and math.cos within one unit in the last place."""
    import math

    from dem_core.engine._angles import SMALL, cosine, sine
    angles = np.concatenate([np.linspace(-1.5 * SMALL, 1.5 * SMALL, 30001), np.geomspace(1e-300, SMALL, 2000)])
    for x in np.concatenate([angles, -angles]):
        assert abs(sine(x) - math.sin(x)) <= np.spacing(abs(math.sin(x))), x
        assert abs(cosine(x) - math.cos(x)) <= np.spacing(math.cos(x)), x
