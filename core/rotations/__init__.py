"""The rotation toolbox: matrices and intrinsic Euler angles (:mod:`.euler`), quaternions, continuity over frames."""
