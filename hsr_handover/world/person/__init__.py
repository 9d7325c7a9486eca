"""The simulated person: body dimensions, aiming joints at points, the scripted behaviour
timeline, taking what the robot holds out. Plain numpy; `world.systems.human_actor` runs it."""
