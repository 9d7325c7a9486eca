"""The world's Drake systems: the person's actor and grip, the head camera, the pose detector
and the wrist's force sensor. Each declares its ports and state and calls a numpy model."""
