"""The pictures of the scenes and of a user's model: the snapshot (raytraced, no display), Exudyn's
live renderer and its SolutionViewer (under Xvfb) are filled by the scene, and hiding the contact's
own graphics takes its surface and net out of the picture. The contact's graphics item by item:
tests/test_graphics.py."""
import math

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")
from exu_aniso.catalog import MODELS  # noqa: E402
from _suite import HANG_S  # noqa: E402

SCENES = list(MODELS)


def _drawn_share(image):
    """Share of the picture's pixels that are not the white background."""
    return float((np.asarray(image) < 245).any(axis=2).mean())


def _without_contact_graphics(mbs, contacts):
    for c in contacts:
        mbs.SetObjectParameter(c["oContact"], "Vshow", False)


# the scenes whose master surface the contact draws (the others' surface is a body's own face, drawn by
# the body: the feeder's plate, the fastening's nut and seat)
# the share of the picture the contact's drawing must change, per scene whose contact draws its surface:
# the fastening's are fine nets about a large bolt (the bearing face's 1.6 head radii, the nut's flank a
# quarter of d2 wide), 2.0 % of the snapshot, 2.7 % of the live window, 3.2 % of the SolutionViewer's
DRAWN_BY_THE_CONTACT = dict(block=0.05, screw=0.05, particle=0.05, capstan=0.05, fastening=0.01, nut=0.01, loosening=0.05,
                            fe_block=0.05, fe_screw=0.05)


def _changed_share(a, b):
    """Share of the pixels that differ between two pictures by more than 30 in a channel."""
    return float((np.abs(np.asarray(a, dtype=int) - np.asarray(b, dtype=int)).max(axis=2) > 30).mean())


@pytest.mark.parametrize("scene", SCENES)
def test_every_scenes_snapshot_shows_its_surface(scene):
    """The picture --snapshot takes (exu_aniso.engines.exudyn_adapter.runner.SnapshotImage, the view
    fitted to everything drawn) is filled by the scene, not a white frame with a dot (the particle
    scene's picture was a ball and an arrow, 7.5 % of the pixels, before its surface was drawn), and
    where the contact draws the master surface, hiding the contact's graphics changes a twentieth of
    the picture or more (the fastening: a hundredth)."""
    from exu_aniso.engines.exudyn_adapter.runner import SnapshotImage
    sc = MODELS[scene]
    model = sc.build(sc.scene.Params())                     # the initial state is pictured: no solve
    contacts = model.get("contacts") or [model["contact"]]
    contacts = list(contacts.values()) if isinstance(contacts, dict) else contacts
    shown = SnapshotImage(model, size=(240, 180))
    assert _drawn_share(shown) > 0.15, (scene, _drawn_share(shown))
    _without_contact_graphics(model["mbs"], contacts)
    hidden = SnapshotImage(model, size=(240, 180))
    if scene in DRAWN_BY_THE_CONTACT:
        assert _changed_share(shown, hidden) > DRAWN_BY_THE_CONTACT[scene], (scene, _changed_share(shown, hidden))


@pytest.mark.parametrize("model", ["rings", "full"])
def test_the_joints_snapshot_shows_the_thread_and_the_faces(model):
    """The loosening's joint (case joint) fills its picture, and its two contacts draw their surfaces
    (the thread's and the plate's nets, the full nut's flank inside a see-through nut): hiding them
    changes a twentieth of the picture or more."""
    from exu_aniso.engines.exudyn_adapter.runner import SnapshotImage
    from exu_aniso.scenes.loosening import LooseningParams
    built = MODELS["loosening"].build(LooseningParams(case="joint", model=model))
    shown = SnapshotImage(built, size=(240, 180))
    assert _drawn_share(shown) > 0.15, _drawn_share(shown)
    _without_contact_graphics(built["mbs"], list(built["contacts"].values()))
    assert _changed_share(shown, SnapshotImage(built, size=(240, 180))) > 0.05


SURFACES = {
    "plane": lambda: __import__("exu_aniso").Plane(),
    "cylinder": lambda: __import__("exu_aniso").Cylinder(0.3, side="outside"),
    "cone": lambda: __import__("exu_aniso").Cone(0.3, 0.5),
    "sphere": lambda: __import__("exu_aniso").Sphere(0.5, axis_direction=(1, 0, 0)),
    "torus": lambda: __import__("exu_aniso").Torus(1.0, 0.3),
    "helicoid": lambda: __import__("exu_aniso.geometry").geometry.Helicoid(0.1, math.pi / 3, 0.4),
    "revolution": lambda: __import__("exu_aniso").SurfaceOfRevolution(_bulge),
}


def _bulge(z):
    """A surface of revolution's profile: r = 0.3 + 0.1 z^2 [m], with r' and r''."""
    return 0.3 + 0.1 * z * z, 0.2 * z, 0.2


@pytest.mark.parametrize("name", sorted(SURFACES))
def test_a_users_model_on_every_surface_is_seen(name):
    """A user's mass point on every surface class, pictured by the one call exu_aniso.Snapshot(mbs):
    the surface is in the picture (hiding the contact's graphics gives back a tenth of it or more)."""
    import exu_aniso
    from exu_aniso import Adhesion, Friction
    surf = SURFACES[name]()
    g = surf.at((0.3, 1.2 if name == "sphere" else 0.2))
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    o = mbs.CreateMassPoint(referencePosition=list(g.point - 1e-6 * g.n), mass=0.1)
    contact = mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=[[0.0, 0.0, 0.0]], surface=surf,
                                           adhesion=Adhesion.isotropic(1e4), friction=Friction.isotropic(0.2),
                                           normalStiffness=1e6, implementation="numpy")   # the drawing alone
    mbs.Assemble()
    shown = exu_aniso.Snapshot(mbs, size=(240, 180))
    _without_contact_graphics(mbs, [contact])
    hidden = exu_aniso.Snapshot(mbs, size=(240, 180))
    assert _drawn_share(shown) > 0.15 and _changed_share(shown, hidden) > 0.1, (name, _changed_share(shown, hidden))


def test_the_blocks_plane_is_drawn_under_its_whole_path():
    """The block on its 8 x 8 grid pushed for 10 s (1 m of driver travel): the drawn polar disk
    (its radius: models.block.drawn_plane_size) covers every position of the block's centre and its
    half-diagonal, where the radius taken from the initial points left the block off its edge."""
    import math
    from exu_aniso.models.block import RunBlock, drawn_plane_size
    from exu_aniso.scenes.block import BlockParams
    p = BlockParams(model="full", points="grid:8", t_end=10.0)
    res = RunBlock(p)
    r = np.hypot(res.trajectory["x"], res.trajectory["y"])
    assert r.max() + p.size / math.sqrt(2) <= drawn_plane_size(p), (r.max(), drawn_plane_size(p))
    assert r.max() > 0.7                        # the block does leave the default disk's 0.6 m


_LIVE = """
import json, sys
import numpy as np
from exu_aniso.catalog import MODELS
out = {}
for scene in sys.argv[1:]:
    sc = MODELS[scene]
    m = sc.build(sc.scene.Params())
    SC, mbs = m["SC"], m["mbs"]
    SC.visualizationSettings.view0.window.renderWindowSize = [320, 240]
    contacts = m.get("contacts") or [m["contact"]]
    contacts = list(contacts.values()) if isinstance(contacts, dict) else contacts
    SC.renderer.Start()
    pictures = []
    for show in (True, False):
        for c in contacts:
            mbs.SetObjectParameter(c["oContact"], "Vshow", show)
        SC.renderer.DoIdleTasks(waitSeconds=0.3)
        SC.renderer.ZoomAll()
        SC.renderer.DoIdleTasks(waitSeconds=0.3)
        pictures.append(np.asarray(SC.renderer.RedrawAndGetImage())[..., :3].astype(int))
    SC.renderer.Stop()
    shown, hidden = pictures
    out[scene] = [float((shown < 245).any(axis=-1).mean()), float((np.abs(shown - hidden).max(axis=-1) > 30).mean())]
print(json.dumps(out))
"""


@pytest.mark.slow
def test_the_live_renderer_frames_every_scene(tmp_path):
    """Exudyn's live renderer (OpenGL in a window, here under Xvfb), zoomed to all: every scene fills
    its picture, and where the contact draws the surface, hiding it changes a twentieth of it (the fastening: a hundredth)."""
    import json
    import shutil
    import subprocess
    import sys
    if shutil.which("xvfb-run") is None:
        pytest.skip("no xvfb-run (apt-get install xvfb): the live renderer needs a display")
    scenes = SCENES
    out = subprocess.run(["xvfb-run", "-a", sys.executable, "-c", _LIVE, *scenes], capture_output=True, text=True,
                         timeout=HANG_S, cwd=tmp_path)
    assert out.returncode == 0, out.stderr[-3000:]
    figures = json.loads(out.stdout.strip().splitlines()[-1])
    for scene in scenes:
        drawn, changed = figures[scene]
        assert drawn > 0.15, (scene, drawn)
        if scene in DRAWN_BY_THE_CONTACT:
            assert changed > DRAWN_BY_THE_CONTACT[scene], (scene, changed)


_VIEWER = """
import json, sys
import numpy as np
import exudyn.interactive as interactive
from exudyn.utilities import LoadSolutionFile
from exu_aniso.catalog import MODELS
from exu_aniso.engines.exudyn_adapter.runner import StoreSolution
scene, show = sys.argv[1], sys.argv[2] == "1"
sc = MODELS[scene]
m = sc.build(sc.scene.Params())
SC, mbs = m["SC"], m["mbs"]
contacts = m.get("contacts") or [m["contact"]]
contacts = list(contacts.values()) if isinstance(contacts, dict) else contacts
StoreSolution(m["simulationSettings"], "solution.bin", frames=20)
mbs.SolveDynamic(m["simulationSettings"], solverType=m["solverType"])
for c in contacts:
    mbs.SetObjectParameter(c["oContact"], "Vshow", show)
SC.visualizationSettings.view0.window.renderWindowSize = [320, 240]
pictures = []


class Watched(interactive.InteractiveDialog):
    # the viewer's own update (a row loaded, the window redrawn), then the window's picture; the
    # render window's stop flag (the user's Escape) ends the viewer after 25 updates: a whole cycle
    def __init__(self, mbs, simulationFunction, **kwargs):
        def update(mbs, dialog):
            simulationFunction(mbs, dialog)
            pictures.append(np.asarray(SC.renderer.RedrawAndGetImage())[..., :3].astype(int))
            if len(pictures) >= 25:
                mbs.SetRenderEngineStopFlag(True)
        super().__init__(mbs, simulationFunction=update, **kwargs)


interactive.InteractiveDialog = Watched
mbs.SolutionViewer(LoadSolutionFile("solution.bin", verbose=False), runMode=0, timeout=0.01)
np.save(f"{scene}_{int(show)}.npy", pictures[-1])
print(len(pictures))
"""


@pytest.mark.slow
def test_the_solution_viewer_frames_every_scene(tmp_path):
    """Exudyn's SolutionViewer (render window and dialog, under Xvfb) on each scene's stored solution,
    a whole cycle of its rows played: the last picture is filled by the scene, and where the contact
    draws the surface, hiding it changes a twentieth of it (the fastening: a hundredth) (the viewer's framing is the scene's own:
    runner.SceneView). 12 runs of the viewer, about 60 s."""
    import shutil
    import subprocess
    import sys
    if shutil.which("xvfb-run") is None:
        pytest.skip("no xvfb-run (apt-get install xvfb): the SolutionViewer needs a display")
    for scene in SCENES:
        for show in ("1", "0"):
            out = subprocess.run(["xvfb-run", "-a", sys.executable, "-c", _VIEWER, scene, show], capture_output=True,
                                 text=True, timeout=HANG_S, cwd=tmp_path)
            assert out.returncode == 0 and out.stdout.split()[-1] == "25", (scene, out.stderr[-3000:])
        shown, hidden = (np.load(tmp_path / f"{scene}_{s}.npy") for s in ("1", "0"))
        assert (shown < 245).any(axis=-1).mean() > 0.15, scene
        if scene in DRAWN_BY_THE_CONTACT:
            assert _changed_share(shown, hidden) > DRAWN_BY_THE_CONTACT[scene], scene
