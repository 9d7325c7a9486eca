"""The perceiving-acting cycle (issue 10): the state machine, its planner on percepts, where
the robot looks and its look round."""
