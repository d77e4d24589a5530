"""The contact history of a point: one row of N_HISTORY numbers that every engine stores and carries
from step to step (the reference in arrays, Exudyn in its data coordinates), and the status codes:
the state of the contact law that the kernel (exu_aniso.kernel.point) reads and writes.

Columns (``HISTORY_FIELDS``, named by the index constants below for the compiled kernel):

* ``traction_1``, ``traction_2`` (``H_T1``, ``H_T2``) [N]: the tangential traction T in the
  orthonormal tangent frame at the anchor;
* ``anchor_1``, ``anchor_2`` (``H_XI1``, ``H_XI2``): the surface coordinates xi of the anchor, the
  contact point at the last accepted step (periodic coordinates unwrapped: they count revolutions);
* ``active`` (``H_ACTIVE``): 1 while the point was in contact at the last accepted step, else 0;
* ``dissipated_energy`` (``H_DISSIPATED``) [J] and ``slip_distance`` (``H_SLIP``) [m]: accumulated;
* ``status`` (``H_STATUS``): the status of the step (below);
* ``normal`` (``H_NORMAL``) [N]: the normal traction N (<= 0).

The last two are outputs for sensors; the law does not read them back.

Status of a contact point in a step, the one set of codes of the package (the return maps give
STICK or SLIP): OPEN 0 (no contact), STICK 1, SLIP 2, UNRESOLVED 3 (the motion in the step cannot
be resolved: the engine must reject the step and retry it smaller).
"""
from __future__ import annotations

HISTORY_FIELDS = ("traction_1", "traction_2", "anchor_1", "anchor_2", "active",
                  "dissipated_energy", "slip_distance", "status", "normal")
N_HISTORY = len(HISTORY_FIELDS)
H_T1, H_T2, H_XI1, H_XI2, H_ACTIVE, H_DISSIPATED, H_SLIP, H_STATUS, H_NORMAL = range(N_HISTORY)

OPEN, STICK, SLIP, UNRESOLVED = 0, 1, 2, 3
STATUS_NAMES = ("open", "stick", "slip", "unresolved")
