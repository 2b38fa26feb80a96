"""Analysis over time: curves of a joint's quantities, foot contacts, the kinematics classroom."""
