"""The handover cycle's thresholds (paper 3.3): the gripper's openings, how long the robot
waits for what, and when it judges the person to reach for, hold or take the object. Each is
in physical terms (m, s, N, degrees) with why it is what it is."""

from __future__ import annotations

import dataclasses


@dataclasses.dataclass(frozen=True)
class CycleParams:
    """The thresholds `cycle.HandoverCycle` decides by; the defaults are the robot's."""

    # The gripper ----------------------------------------------------------------------------

    held_opening: float = 0.01
    """m: a gripper closed on an object reads at least this (closed on nothing it reads ~0)."""
    open: float = 0.1
    """m of opening to approach with (and to put an object down, or when a failure leaves
    nothing in the hand); the move is planned at the plan's own opening (the object's width
    and 3 cm, `planner.plan_grasp`), up to 1 cm off this."""
    let_go: float = 0.03
    """m the fingers open beyond the object's width to let go (never beyond `open`): no wider,
    so the finger on the person's side does not sweep into the hand that has just taken the
    object."""
    closed: float = 0.0
    """m commanded to grasp: the fingers stop on the object."""
    settle_s: float = 0.8
    """s the gripper is given to close or open."""

    # Lifting and looking --------------------------------------------------------------------

    rise: float = 0.03
    """m the object must rise with the hand, seen by the camera, for a grasp to count."""
    look_s: float = 0.8
    """s the robot looks at the person, the object lifted, before it plans the way to them."""
    seek_s: float = 1.5
    """s the robot looks for the object asked for before it plans the grasp without having seen
    it since the request: the head's turn down from a standing person's face (0.6 rad at
    0.8 rad/s) and a few decisions."""
    patience_s: float = 6.0
    """s the robot keeps trying a plan that finds no way, on fresh percepts, before it gives
    up: a pointing arm held over the object blocks every grasp until the person lowers it (of
    7 grasps that gave up as unreachable, 6 were planned while the person still pointed)."""
    retry_every_s: float = 1.0
    """s between those tries."""

    # Carrying ---------------------------------------------------------------------------------

    recheck_s: float = 0.5
    """s between checks of the carry still to go against the person as seen now: a person
    moves while the robot carries (a pointing arm comes to rest on the table), and a carry
    planned against the arm as it was ran into the hand at rest. A check rebuilds the planning
    scene (about 0.1 s of wall time)."""
    carry_clear: float = -0.03
    """m: a carry whose rest comes nearer than this to the person's perceived capsules stops
    and is planned again from where the robot stands. Negative: 3 cm into the capsules'
    margin (`perceived_scene.PERSON_MARGIN`, 5 cm), still 2 cm off the skeleton. A hand
    come to rest on the carry's way lies deeper (11 cm), while the lifted skeleton of a
    person at rest moves a centimetre or two between frames: a carry, planned
    `trajectory.COLLISION_BOUND` clear of the capsules as they were, checked at zero stopped
    four more times for that alone (0.2 to 1.9 cm in)."""
    carry_clear_slack: float = 0.02
    """m deeper than where the robot stands that a carry's way may come into the person's
    capsules, where the robot already stands deeper than `carry_clear` (`cycle._check_way`):
    the held object carried past the camera hid a seated person's hands, their keypoints were
    lifted onto it, and carries stopped for a person a metre away, 8-17 cm deep in them."""
    still_speed: float = 0.05
    """m/s: a palm slower than this holds the object still, as a person sees it: people reach
    for an object that has come to rest in front of them (`offer_watch`)."""
    offered_s: float = 0.3
    """s the palm must stay still, carrying, for the object to look held out: a carry stopped
    to be planned again, or crawling, within the person's reach is presented where it is."""
    go_on_s: float = 4.0
    """s an object so presented waits before the robot carries it on to the handover point,
    if the person's hand is then seen farther than `reach` from it: a person who reaches for an
    object held still has taken it by then (0.3 s to see it still, a reaction of 0.5 s, the
    reach, the hand closing and tugging: 2.5 s), and one judged within a leaning reach may not
    lean (presented 0.67 m from a seated person's shoulder, a box waited 12 s for a hand that
    never came). A hand not seen is often at the object, hidden by the robot's own arm."""

    # Following the person's hand while presenting -------------------------------------------

    offer: float = 0.2
    """m from a hand held out elsewhere that the robot aims to bring the object to: in front of
    the fingers, for the person to close them on (the wrist itself is inside the person's hand).
    Along the forearm's line that point lies inside the perceived forearm's capsule, so the
    planner holds the object out at the nearest point beside the hand where it fits
    (`planning.offer`): for a wrist held out 32 cm off, every follow, once a second for 12 s,
    found no IK solution at the point itself."""
    follow_beyond: float = 0.45
    """m: a hand held out farther than this from the palm is followed; a nearer one is reaching
    for the object, and the robot holds still for it (following a hand that had just closed on
    the object pushed the gripper into it)."""
    offer_first_s: float = 1.5
    """s a hand held out farther than `follow_beyond` must stay still, with the object held
    out, before the robot brings the object to it: time for the person to see the object held
    still and begin to reach for it where it is (the simulated person takes 0.8 s, a reaction
    time of 0.5 s among them). A follow begun at once toward a hand at rest on the table set
    off as the person reached for where the object had been, and a finger met the hand. A hand
    that moves is reaching, or not yet held out."""
    nudge_s: float = 3.0
    """s a hand may stay still nearer than `follow_beyond` before the robot brings the object to
    it all the same: the person judges it out of their reach (a wrist held out 32 cm off was
    left waiting 12 s). A hand that reaches for the object moves. Held out or resting makes no
    difference: the skeleton cannot tell them apart (the seated person's forearm rests level,
    its wrist about 29 cm below the shoulder; a held-out wrist was seen 30 cm below), and a
    person who does not take the object has it brought nearer, then kept."""
    coming: float = 0.02
    """m a followed hand comes toward the palm, from where it was as the robot set off toward
    it, that means it reaches for the object (the wrist's keypoint wanders under 1 cm along that
    line in a decision or two; a reaching hand is hidden by the robot's own arm within 0.2 s of
    moving 3 cm)."""
    hand_still: float = 0.04
    """m: a hand that stays within this of where it came to rest is waiting (the skeleton's
    wrist wanders 1-2 cm); one that moves farther comes to rest again where it is now."""
    follow_every_s: float = 1.0
    """s between tries to follow the hand (a hand out of reach fails each)."""

    # Feeling the object taken -----------------------------------------------------------------

    reach: float = 0.32
    """m: the person's hand this near the palm counts as at the object: the wrist keypoint sits
    about 27 cm from the centre of an object the person closes a hand on (a hand's length behind
    fingertips a few cm short of it), plus the skeleton's few cm of error."""
    pull: float = 0.01
    """m the palm may be pulled off its commanded point, still, before the robot lets go: the
    person has hold of the object and draws it in (the arm's own sag is under 3 mm). Pulled so
    far while it moves toward the hand, the robot stops there and feels again."""
    spread: float = 0.015
    """m the fingers may be forced open beyond the object's width, while presenting, before the
    robot lets go: the person draws the object out between them (the gripper yields before the
    arm does, so the palm is not pulled). Not when the wrist feels the object knocked across
    (`take.TakeDetector`): a hand striking it on its way in forces them open too."""
    tug: float = 3.0
    """N: the wrist's sensor feeling the load pulled this much harder toward the person than
    while it was carried, at two decisions in a row (0.1 s apart), means the person has hold of
    it. People tug at 5-15 N to take an object; the arm's own accelerations while presenting
    move a few hundred grams, under 1 N; a hand knocking the object on its way in is felt at
    one decision only (3-5 N for a step: letting go at one decision let go of objects before
    the hand had closed on them). The pull must also point within `tug_cone_deg` of the
    person: a hand closing on the object from the side pushes it sideways and up (7 N across,
    4 N toward the person)."""
    tug_cone_deg: float = 45.0
    """degrees off the direction from the palm to the person within which a change of the load
    is a pull toward the person; farther off it is a push across, or a knock."""
    held_across_s: float = 0.3
    """s a load pulled across by over `tug` (more than `tug_cone_deg` off the way to the person)
    must be felt at every decision, the fingers not forced apart, to mean the person has hold
    of the object: a knock is felt at one decision and forces the fingers apart, a hand closing
    on the object from the side holds it by the time it tugs (0.3 s after closing), and a
    person whose hand takes the object beside the robot's fingers can draw it in sideways, 4-10
    N at 45-70 degrees off the shoulder, never a tug (the demo's person did for 0.9 s, and the
    robot let go only as the object left its fingers)."""
    taken_s: float = 1.0
    """s after a hand was last seen at the object, or the object felt held, within which fingers
    that close on nothing mean the person drew it out (the wrist is soon farther off than
    `reach` as the arm draws it in, and the robot's own arm often hides the hand from its
    camera). Held is a tug, or a load pulled across by over `tug` while the fingers still hold,
    whichever way and if only at one decision: gravity pulls a slipping object only down (a
    hand the arm hides can draw the cup out with 9 N across, 63 degrees off the person, over a
    second, or yank it out across and up within 0.1 s; read as drops, both would be failures).
    A knock across that shook the object loose would be read as a take too: the fingers are
    empty by then, so letting go changes only what the robot reports."""
    empty_s: float = 0.5
    """s the robot holds still after its fingers close on nothing while carrying or presenting,
    with no hand seen at the object nor tug felt, before it looks where the object went: a
    dropped object falls from the presenting height to the table in about 0.25 s."""
    still_up: float = 0.08
    """m above where the object stood on the table that the camera must see it, `empty_s` after
    the fingers closed on nothing, to count it taken rather than dropped: a hand the robot's own
    arm hid from its camera drew it out (the wrist unseen for the whole presentation, the tug
    pointing down and away). Held out, it is 15-30 cm up."""

    # Giving up ------------------------------------------------------------------------------

    wait_s: float = 12.0
    """s the robot presents the object before it gives up (HandoverSim's 13 s limit)."""
    lost_s: float = 2.0
    """s while presenting without seeing any of the person (the neck, a shoulder, the face) or
    their receiving hand: the person withdrew. The robot's own arm often hides a shoulder while
    the hand takes the object (a shoulder alone was not enough: the robot gave up on a person
    pulling at the object, the wrist in view); presenting to a standing person at their chest,
    the arm and the object can hide the whole torso, and only the eyes show over them."""
