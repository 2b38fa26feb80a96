"""Forward kinematics: the numpy reference (:mod:`.fk`), the compiled engine (:mod:`.engine`),
and the post- to pre-rotation conversion (:mod:`.convention`)."""
