"""The perceiving-acting cycle (paper 3.3): the state machine (`cycle`), what it works on
(`cycle_types`) and decides by (`cycle_params`), feeling the object taken (`take`), following
the person's hand (`hand_follower`), putting an object back (`put_back`), its planner on
percepts, where the robot looks and its look round. Plain Python;
`robot.systems.handover_supervisor` runs it."""
