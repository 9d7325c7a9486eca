"""The robot's Drake systems: each declares its ports and state and calls an algorithm from
`robot.perception`, `robot.intent` or `robot.handover` (the supervisor steps the cycle)."""
