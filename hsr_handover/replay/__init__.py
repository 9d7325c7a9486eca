"""What is drawn: the Meshcat recording and its offline HTML replay, and the visualisers of
what the robot thinks (rays, target, plans, maps) and of the scene map."""
