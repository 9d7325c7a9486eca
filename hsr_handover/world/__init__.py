"""The simulated world: the station (plant, scene, camera), the simulated person and the
sensor models, including the simulated pose detector. The robot never imports it; the two meet
only at the ports named in `hsr_handover.interface`."""
