"""The robot's perception algorithms on numpy arrays (paper 3.1-3.2): the scene's Growing
Neural Gas map, attention, the object detector, the table fit, the skeleton lifted from depth,
the torso's facing and where the head looks. No Drake here."""
