"""The simulated person (layer 1): body dimensions, aiming joints at points, the scripted
behaviour timeline. Plain numpy; the HumanActor system wraps it."""
