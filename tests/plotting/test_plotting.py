"""Figures build for one- and two-body models, with the right panels; the GIF is written."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

import vibss
from vibss.errors import ModelError
from vibss.plotting import animate_mode, plot_energy, plot_model, plot_modes
from vibss.plotting._scene import Scene, box_half_sides


@pytest.fixture(scope="module")
def prism_modes(request):
    from cases.models import prism_model

    return vibss.modes(prism_model())


@pytest.fixture(scope="module")
def two_modes():
    from cases.models import two_mass_model

    return vibss.modes(two_mass_model())


def test_box_has_the_body_inertia():
    m, (a, b, c) = 30.0, (0.4, 1.0, 2.2)          # uniform box: I1 = m (b^2 + c^2) / 12 ...
    moments = m / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    assert np.allclose(2 * box_half_sides(m, moments), [a, b, c])


def test_iso_one_panel_per_mode(prism_modes):
    fig = plot_modes(prism_modes)
    assert len(fig.axes) == 6
    assert all(ax.name == "3d" for ax in fig.axes)
    titles = [ax.get_title() for ax in fig.axes]
    assert titles[0] == "mode 1: 1.01 Hz (60 CPM), x"
    assert fig.axes[0].get_xlabel() == "x [m]" and fig.axes[0].get_zlabel() == "z [m]"


def test_three_views_per_mode(two_modes):
    fig = plot_modes(two_modes, which=[0, 5], view="three")
    assert len(fig.axes) == 6
    assert [ax.get_xlabel() for ax in fig.axes[:3]] == ["x [m]", "y [m]", "x [m]"]
    assert [ax.get_ylabel() for ax in fig.axes[:3]] == ["z [m]", "z [m]", "y [m]"]


def test_single_view_and_given_axes(two_modes):
    assert len(plot_modes(two_modes, which=range(4), view="xz").axes) == 4
    fig = plot_modes(two_modes, which=[2], view="yz", ax=plot_model(two_modes.model, view="xy").axes[0])
    assert len(fig.axes) == 1


def test_deformed_shape_has_the_requested_scale(prism_modes):
    scene = Scene.of(prism_modes.model)
    from vibss.plotting.modes import mode_motion

    q, length = mode_motion(prism_modes, 0, scene, scale=0.25)
    assert length == 0.25
    assert scene.max_displacement(q) == pytest.approx(0.25)
    moved = scene.moved(q)
    assert np.allclose(moved.cogs[0] - scene.cogs[0], [0.25, 0, 0])   # pure x mode


def test_bad_arguments(prism_modes):
    with pytest.raises(ModelError, match="view"):
        plot_modes(prism_modes, view="perspective")
    with pytest.raises(ModelError, match="which"):
        plot_modes(prism_modes, which=[6])
    with pytest.raises(ModelError, match="kind"):
        plot_energy(prism_modes, kind="pie")


def test_energy_and_model_figures(two_modes):
    fig = plot_energy(two_modes)
    assert len(fig.axes[0].get_xticklabels()) == 12       # one column per body DOF
    assert fig.axes[1].get_ylabel() == "kinetic energy [%]"
    assert len(plot_energy(two_modes, kind="bar").axes) == 1
    assert len(plot_model(two_modes.model, view="three").axes) == 3


def test_model_marks_control_points():
    from cases.models import asymmetric_model

    model = asymmetric_model()
    body = model.bodies[0].name
    model = model.replace(control_points=[vibss.ControlPoint("sensor", body, [0.1, 0.0, 0.2])])
    fig = plot_model(model)
    texts = {t.get_text().strip() for t in fig.axes[0].texts}
    assert {b.name for b in model.bodies} <= texts
    assert "sensor" in texts


def test_gif_written(prism_modes, tmp_path):
    out = animate_mode(prism_modes, 3, tmp_path / "rx.gif", frames=4, view="yz")
    data = out.read_bytes()
    assert data[:6] in (b"GIF89a", b"GIF87a") and len(data) > 1000


def test_modes_plot_method(prism_modes):
    assert len(prism_modes.plot(which=[0]).axes) == 1


def test_springs_are_drawn_along_the_stiffest_local_axis():
    """Issue 16: the torque strut (stiff along its rod, local axis 1 = global y) was drawn vertical.
    Each spring symbol is parallel to the local axis with the largest stiffness, pointing up."""
    model = vibss.load_example("powertrain")
    scene = Scene.of(model)
    for k, m in enumerate(model.mounts):
        t = m.orientation.matrix
        k_axis = np.asarray(m.type.stiffness, float)[:3]
        stiffest = [j for j in range(3) if k_axis[j] == k_axis.max()]
        d = scene.spring_axis[k]
        assert np.isclose(np.linalg.norm(d), 1.0)
        assert max(abs(float(d @ t[:, j])) for j in stiffest) == pytest.approx(1.0)
        assert d[2] >= -1e-12
    strut = [k for k, m in enumerate(model.mounts) if m.name == "torque-strut"][0]
    assert np.allclose(np.abs(scene.spring_axis[strut]), [0.0, 1.0, 0.0], atol=1e-9)   # along its rod


def test_spring_direction_ties_take_the_most_vertical_axis():
    from scipy.spatial.transform import Rotation

    from vibss.plotting._scene import spring_direction

    t = Rotation.from_euler("x", 30, degrees=True).as_matrix()       # axis 3 tilted 30 deg about x
    assert np.allclose(spring_direction(t, [1e4, 1e4, 1e4]), t[:, 2])
    assert np.allclose(spring_direction(t, [1e4, 3e4, 1e4]), -t[:, 1] if t[2, 1] < 0 else t[:, 1])
    assert np.allclose(spring_direction(np.eye(3), [5e3, 1e3, 1e3]), [1.0, 0.0, 0.0])  # horizontal: +x


@pytest.mark.parametrize("example, view", [("powertrain", "three"), ("powertrain", "iso"), ("two_mass", "iso"),
                                           ("platform", "three")])
def test_model_labels_do_not_overlap(example, view):
    """Greedy placement: no two names overlap and every name is inside the figure."""
    fig = plot_model(vibss.load_example(example), view=view)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    model = vibss.load_example(example)
    names = {b.name for b in model.bodies} | {m.name for m in model.mounts} | {c.name for c in model.control_points}
    for ax in fig.axes:
        boxes = [t.get_window_extent(renderer) for t in ax.texts if t.get_text() in names]
        assert len(boxes) == len(names)
        for i in range(len(boxes)):
            b = boxes[i]
            assert b.x0 >= 0 and b.y0 >= 0 and b.x1 <= fig.bbox.x1 and b.y1 <= fig.bbox.y1
            for c in boxes[i + 1:]:
                assert not (min(b.x1, c.x1) - max(b.x0, c.x0) > 0.5 and min(b.y1, c.y1) - max(b.y0, c.y0) > 0.5)


def test_energy_title_fits_in_its_figure():
    """Issue 16: the energy map's title ran off both edges for the powertrain's long name."""
    import vibss
    from vibss.plotting import plot_energy

    fig = plot_energy(vibss.modes(vibss.load_example("powertrain")))
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    width = fig.get_figwidth() * fig.dpi
    titles = [ax.title for ax in fig.axes if ax.get_title()]
    assert titles
    for t in titles:
        box = t.get_window_extent(renderer)
        assert box.x0 >= 0 and box.x1 <= width, (box, width)


def test_model_drawing_keeps_body_outlines_apart_from_the_mount_axis_colours(two_modes):
    """The first body's colour (C0) was the mount axis 3 colour (tab:blue) in the model drawing."""
    from matplotlib.colors import same_color

    from vibss.plotting.layout import AXIS_COLORS

    fig = plot_model(two_modes.model, view="xz")
    lines = [ln for ln in fig.axes[0].get_lines() if ln.get_linewidth() == 1.6]    # the outlines
    assert len(lines) == len(two_modes.model.bodies)
    for ln in lines:
        assert not any(same_color(ln.get_color(), c) for c in AXIS_COLORS)
    legend = {t.get_text(): h for t, h in zip(fig.legends[0].get_texts(), fig.legends[0].legend_handles)}
    assert not any(same_color(legend["body outline"].get_color(), c) for c in AXIS_COLORS)
