"""Quality checks of a motion: what is broken, at which frames and joints.

``run_checks(motion, settings) -> list[Finding]`` runs the checks of
:class:`CheckSettings.kinds <core.checks.model.CheckSettings>`, vectorised over frames, with
every threshold relative to the motion's size (:attr:`core.model.motion.Motion.size`) and rate,
so they hold in centimetres, metres or inches and from 24 to 240 Hz:

==============  ======================================================  =====================
kind            what                                                    module
==============  ======================================================  =====================
foot-skate      a planted foot sliding across the ground                :mod:`.feet`
penetration     a foot below the level it is planted at                 :mod:`.feet`
pop             a joint knocked away for one frame                      :mod:`.spikes`
jitter          noise on a joint's path                                 :mod:`.spikes`
flip            a local rotation jumping (Euler wrap, sign turned)      :mod:`.joints`
bone-length     a bone that can stretch (translation channels) does     :mod:`.joints`
frozen          the pose held still for a stretch of frames             :mod:`.frames`
duplicate       a frame repeated                                        :mod:`.frames`
teleport        a root jumping beyond its own velocity                  :mod:`.spikes`
rest-pose       T-pose (rest) frames left at the start or end           :mod:`.frames`
==============  ======================================================  =====================

:func:`skipped_frames` lists the frames some checks leave out and why (the rest-pose frames
at the ends, which only ``rest-pose`` looks at: :class:`Skipped`). :func:`joint_flags`
turns findings into an (F, J) array of severity levels (for colours); :mod:`.report` gives
the JSON of ``gmr check`` and its table. Formulas, thresholds and what
the checks say about the real files: docs/checks.md.
"""

from gmr_studio.core.checks.model import KINDS, SEVERITIES, CheckSettings, Finding, Skipped, joint_flags
from gmr_studio.core.checks.run import CHECKS, run_checks, skipped_frames

__all__ = [
    "CHECKS",
    "KINDS",
    "SEVERITIES",
    "CheckSettings",
    "Finding",
    "Skipped",
    "joint_flags",
    "run_checks",
    "skipped_frames",
]
