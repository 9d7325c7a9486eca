"""The perceiving-acting cycle (paper 3.3): the state machine, its planner on percepts, where
the robot looks and its look round. Plain Python; `robot.systems.handover_supervisor` runs it."""
