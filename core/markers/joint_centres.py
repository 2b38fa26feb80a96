"""Joint centres from skin markers, by the published methods gait labs use.

Every function is vectorised over leading axes (frames): points are ``(..., 3)`` in
millimetres (the regressions' coefficients are in mm), results the same shape.

- :func:`pelvis_frame`: origin at the mid-point of the ASIS markers, ``x`` anterior, ``y`` to
  the left (RASI -> LASI), ``z`` up, perpendicular to the plane of the ASIS and the sacrum
  (Davis et al. 1991; Vicon Plug-in Gait).
- :func:`hip_harrington`: Harrington M.E., Zavatsky A.B., Lawson S.E.M., Yuan Z., Theologis
  T.N. (2007) "Prediction of the hip joint centre in adults, children, and patients with
  cerebral palsy based on magnetic resonance imaging", J. Biomech. 40:595-602, the regression
  on pelvis width PW (ASIS to ASIS) and depth PD (mid-ASIS to mid-PSIS), in their ISB frame
  (x anterior, y superior, z to the right): ``x = -0.24 PD - 9.9``, ``y = -0.30 PW - 10.9``,
  ``z = 0.33 PW + 7.3`` mm (right hip; the left mirrors z).
- :func:`hip_davis`: Davis R.B., Ounpuu S., Tyburski D., Gage J.R. (1991) "A gait analysis
  data collection and reduction technique", Hum. Mov. Sci. 10:575-587, as Plug-in Gait
  implements it: ``C = 0.115 LL - 15.3``, ``theta = 0.5 rad``, ``beta = 0.314 rad``,
  ``X_dis = 0.1288 LL - 48.56`` (ASIS-trochanter distance) and ``r`` the marker radius;
  ``x = C cos(theta) sin(beta) - (X_dis + r) cos(beta)``, ``y = +-(aa - C sin(theta))``
  (aa half the ASIS distance; + left), ``z = -C cos(theta) cos(beta) - (X_dis + r) sin(beta)``.
- :func:`chord`: Plug-in Gait's chord function (Davis et al. 1991; Vicon Plug-in Gait
  reference guide, "Knee and ankle joint centres"): the joint centre J lies in the plane of
  the proximal joint centre P, the lateral marker L and a wand marker W, at ``delta =
  width / 2 + marker radius`` from L, with the angle P-J-L a right angle. In the triangle
  P-J-L, ``cos(angle at L) = delta / |P - L|``, so
  ``J = L + delta (cos a u - sin a w)`` with ``u`` the unit vector from L to P and ``w`` the
  unit component of ``W - L`` perpendicular to u (J is on the side away from the wand).
- :func:`midpoint`: the centre between lateral and medial markers (knee epicondyles,
  malleoli, humeral epicondyles, wrist styloids / wrist bar), as CGM 2.x (Leboeuf et al.
  2019, pyCGM2) and Qualisys' and OpenSim's gait models place the knee, ankle, elbow and
  wrist when the medial markers are there.
- :func:`shoulder_rab`: Rab G., Petuskey K., Bagley A. (2002) "A method for determination of
  upper extremity kinematics", Gait Posture 15:113-119: the glenohumeral centre 17% of the
  acromion-to-acromion distance below the acromion (shoulder) marker, along the thorax's
  vertical axis.
- :func:`thorax_up`: Plug-in Gait's thorax vertical: from mid(T10, STRN) to mid(C7, CLAV).
"""

from __future__ import annotations

import numpy as np

#: Plug-in Gait's default marker diameter (mm)
MARKER_DIAMETER = 14.0
#: Harrington et al. 2007 coefficients (mm): x from PD, y (superior) and z (lateral) from PW
HARRINGTON = {"x": (-0.24, -9.9), "y": (-0.30, -10.9), "z": (0.33, 7.3)}
#: Davis et al. 1991 constants
DAVIS_THETA, DAVIS_BETA = 0.5, 0.314
#: Rab et al. 2002: the shoulder centre below the acromion marker, share of the acromion distance
RAB_SHOULDER = 0.17


def unit(v: np.ndarray) -> np.ndarray:
    """(..., 3) vectors scaled to length 1 (NaN stays NaN)."""
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def pelvis_frame(lasi: np.ndarray, rasi: np.ndarray, sacrum: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Origin (..., 3) at mid-ASIS and rotation (..., 3, 3) whose columns are x anterior,
    y left, z up (Davis et al. 1991)."""
    origin = 0.5 * (lasi + rasi)
    y = unit(lasi - rasi)
    z = unit(np.cross(origin - sacrum, y))
    x = np.cross(y, z)
    return origin, np.stack([x, y, z], axis=-1)


def hip_harrington(pelvis_width: np.ndarray, pelvis_depth: np.ndarray) -> np.ndarray:
    """Both hip centres in the pelvis frame (x anterior, y left, z up), mm:
    ``(..., 2, 3)``, index 0 the left hip, 1 the right (Harrington et al. 2007)."""
    pw, pd = np.asarray(pelvis_width, dtype=np.float64), np.asarray(pelvis_depth, dtype=np.float64)
    x = HARRINGTON["x"][0] * pd + HARRINGTON["x"][1]
    up = HARRINGTON["y"][0] * pw + HARRINGTON["y"][1]
    lateral = HARRINGTON["z"][0] * pw + HARRINGTON["z"][1]
    left = np.stack([x, lateral, up], axis=-1)
    right = np.stack([x, -lateral, up], axis=-1)
    return np.stack([left, right], axis=-2)


def hip_davis(
    leg_length: np.ndarray, asis_distance: np.ndarray, marker_radius: float = MARKER_DIAMETER / 2, asis_trochanter=None
) -> np.ndarray:
    """Both hip centres in the pelvis frame (x anterior, y left, z up), mm: ``(..., 2, 3)``,
    left then right (Davis et al. 1991, as Plug-in Gait computes it)."""
    ll = np.asarray(leg_length, dtype=np.float64)
    aa = 0.5 * np.asarray(asis_distance, dtype=np.float64)
    x_dis = 0.1288 * ll - 48.56 if asis_trochanter is None else np.asarray(asis_trochanter, dtype=np.float64)
    c = 0.115 * ll - 15.3
    ct, st, cb, sb = np.cos(DAVIS_THETA), np.sin(DAVIS_THETA), np.cos(DAVIS_BETA), np.sin(DAVIS_BETA)
    x = c * ct * sb - (x_dis + marker_radius) * cb
    y = aa - c * st
    z = -c * ct * cb - (x_dis + marker_radius) * sb
    x, y, z = np.broadcast_arrays(x, y, z)
    return np.stack([np.stack([x, y, z], -1), np.stack([x, -y, z], -1)], axis=-2)


def chord(proximal: np.ndarray, lateral: np.ndarray, wand: np.ndarray, delta) -> np.ndarray:
    """Plug-in Gait's chord function: the joint centre (..., 3) at ``delta`` from the lateral
    marker, in the plane of proximal, lateral and wand, with a right angle at the centre."""
    to_proximal = proximal - lateral
    distance = np.linalg.norm(to_proximal, axis=-1, keepdims=True)
    u = to_proximal / distance
    towards_wand = wand - lateral
    w = unit(towards_wand - np.sum(towards_wand * u, axis=-1, keepdims=True) * u)
    delta = np.asarray(delta, dtype=np.float64)[..., None] if np.ndim(delta) else float(delta)
    cosine = delta / distance
    sine = np.sqrt(np.clip(1.0 - cosine**2, 0.0, None))
    return lateral + delta * (cosine * u - sine * w)


def midpoint(lateral: np.ndarray, medial: np.ndarray) -> np.ndarray:
    """The centre between a lateral and a medial marker."""
    return 0.5 * (lateral + medial)


def thorax_up(c7: np.ndarray, clav: np.ndarray, t10: np.ndarray, strn: np.ndarray) -> np.ndarray:
    """Plug-in Gait's thorax vertical (..., 3): unit vector from mid(T10, STRN) to mid(C7, CLAV)."""
    return unit(0.5 * (c7 + clav) - 0.5 * (t10 + strn))


def shoulder_rab(shoulder: np.ndarray, other_shoulder: np.ndarray, up: np.ndarray) -> np.ndarray:
    """The glenohumeral centre (..., 3): the shoulder marker moved down the thorax vertical by
    17% of the distance between the two shoulder markers (Rab et al. 2002)."""
    width = np.linalg.norm(shoulder - other_shoulder, axis=-1, keepdims=True)
    return shoulder - RAB_SHOULDER * width * up
