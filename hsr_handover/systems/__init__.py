"""Drake LeafSystems (layer 2): each declares its ports and state and calls a layer-1 algorithm."""
