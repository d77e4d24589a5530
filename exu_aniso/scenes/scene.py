"""What a scene is, to every engine and to the command line: the ``Scene`` interface.

A scene module (``exu_aniso.scenes.<name>``) defines its parameters (a ``SceneParams``), its contact
law and points, its closed forms, its summary and energy ledger and its plot, and ends with one
object, ``SCENE``, an instance of a ``Scene`` subclass that names them. Everything that runs a
scene asks this object and nothing else:

* the Exudyn model script (``exu_aniso.models.<name>``) builds the model and reads its trajectory
  back; ``engines.exudyn_adapter.runner.ModelScript`` solves it and calls ``summary`` and
  ``ledger`` with what it read;
* the reference engine's function, where the scene has one (``reference``);
* the catalog and the command line (``name``, ``Params``, ``columns``, ``title_keys`` (through
  ``title_keys_for(p)``), ``plot``, ``figsize``).

The interface, for a scene's parameters ``p`` (an instance of ``Params``):

* ``law(p)``: the contact law, a ``ContactLaw``, or a dict name -> ContactLaw for a scene with
  several contacts;
* ``points(p)``: the contact points in the body's frame [m], an array (K, 3), or a dict name ->
  array for several contacts (a body that is a mesh: the points on its reference configuration);
* ``closed_forms(p)``: the scene's closed forms for ``p``, a dict name -> value (each name carries
  its unit as the summary's keys do); a value is None where ``p`` is outside the closed form's
  domain, with the reason under ``"undefined"`` (as in a summary);
* ``summary(traj, p, wall_s, steps, newton_iterations, **inputs)``: the summary of a run of any
  engine (the trajectory as dict name -> array with ``columns``' names; ``wall_s`` NaN for a run
  that failed; ``inputs``: what the scene needs beyond the trajectory, documented by the scene);
* ``ledger(p, traj, **inputs)``: the energy ledger of a completed run (adds the ledger's columns to
  ``traj``, returns the summary's ledger entries); ``inputs``, the ledger's inputs, are what an
  engine reads back beyond the trajectory (the contact's history, the bodies' motion, ...), named
  by the scene's ``*_energy`` function;
* ``plot(traj, p, fig)``: draws trajectory.png on a matplotlib Figure of ``figsize`` [in];
* ``reference(p, **options)``: the run of the reference engine, a ``Result``, or None (the
  attribute) where the scene has no reference model.

Adding a scene: its module with a ``Scene`` subclass and ``SCENE``, its model script with a
``ModelScript``, and one line in ``exu_aniso.catalog``.
"""
from __future__ import annotations


class Scene:
    """A scene, as the module docstring says. Subclasses set the class attributes and implement the
    methods; ``reference`` stays None where the scene has no reference model."""

    name: str = ""                  # the command line's name of the scene
    Params: type = None             # its SceneParams subclass
    columns: dict = {}              # trajectory.csv's columns -> SI unit
    title_keys: tuple = ()          # the two summary values in trajectory.png's title
    figsize: tuple = (6.0, 5.0)     # of trajectory.png [in]
    reference = None                # (p, **options) -> Result of the reference engine, or None

    def title_keys_for(self, p):
        """The summary keys in trajectory.png's title for the parameters p (a scene whose cases report
        different values overrides it); ``title_keys``."""
        return self.title_keys

    def law(self, p):
        raise NotImplementedError

    def points(self, p):
        raise NotImplementedError

    def closed_forms(self, p):
        raise NotImplementedError

    def summary(self, traj, p, wall_s, steps, newton_iterations, **inputs):
        raise NotImplementedError

    def ledger(self, p, traj, **inputs):
        raise NotImplementedError

    def plot(self, traj, p, fig):
        raise NotImplementedError

    def __repr__(self):
        return f"<scene {self.name}>"
