#!/usr/bin/env python3
"""Writes scenes/actors/footholds.lm: a field of stepping stones for
walk_stepworthy (thesis 5.9). The stones stand on a jittered grid with
some left out (a fixed seed); one of them sinks during the walk. With
--walker, scenes/actors/walker_stones.lm: the same walk by a person
(the built-in humanoid held by its eyes, 1.6 m up) over stones set
closer, a person's step apart.

    python3 scripts/stepping_stones.py > scenes/actors/footholds.lm
    python3 scripts/stepping_stones.py --walker > scenes/actors/walker_stones.lm

The stone list is also what tests/actors/footholds.rs checks the walk
against (it reads the `f` lines of the scene back)."""

import random
import sys

WALKER = "--walker" in sys.argv[1:]

SPACING = 0.44 if WALKER else 0.62
HALF = 0.12 if WALKER else 0.15  # stones the size of a foot
DEPTH = 0.3          # water surface below the stones' tops (y = 0)
BASE = 1.5           # the stones reach this far down, under the water
KEEP = 0.86 if WALKER else 0.72
SINK_AT = (0.04, 0.26)   # the stone that sinks
SINK_T = 3.8              # when it starts to sink, seconds
SEED = 1997

rng = random.Random(SEED)
stones = []
(I0, I1, J0, J1) = (-7, 8, -8, 8) if WALKER else (-5, 6, -6, 6)
JITTER = 0.05 if WALKER else 0.07
for i in range(I0, I1):
    for j in range(J0, J1):
        x = i * SPACING + rng.uniform(-JITTER, JITTER)
        z = j * SPACING + rng.uniform(-JITTER, JITTER) + SPACING / 2
        keep = rng.random() < KEEP
        near_start = abs(i - I0) + abs(j - J0) <= 1
        if keep or near_start:
            stones.append((round(x, 2), round(z, 2)))

def sinking(x, z):
    return abs(x - SINK_AT[0]) < 0.2 and abs(z - SINK_AT[1]) < 0.2

# Both walks' set: the sky, clouds, the sun, the water.
SET = f"""/* sky, clouds, the sun, the water */
D () (15)
D () (16)
l () () () (12) (0.5) (0.7_) (0.35)
[ m () (3) m () () () (1) (0.10) (0.22) (0.30) D () (2) () () ({DEPTH}_) ]
"""

# The walker starts standing on the stone nearest the cube's start.
START = min(stones, key=lambda s: (s[0] + 3.1) ** 2 + (s[1] + 3.4) ** 2)

if WALKER:
    HEADER = f"""/* A person on stepping stones (thesis 5.9, 7.3.2; issue 39): the
   walk of scenes/actors/footholds.lm by the built-in humanoid. Actor 0
   runs walk_stepworthy over {len(stones)} stones ({2 * HALF} x {2 * HALF}, tops at
   y = 0, {SPACING} apart on a jittered grid with gaps, water {DEPTH}
   below), to two destinations in turn; its steps are shorter than 0.5
   (foothold_step), a person's stride. Its body (D 50, held by its eyes
   1.6 up: 1.76 m tall) stands each foot on the foothold the plan chose
   for it, lifts the other over the water to the next, turns on the spot
   with its feet together and follows its gaze with its head. Its map
   keeps only footholds of 12 voxels or more (half a stone): a stone
   seen far off at a grazing angle is no foothold yet. It sees
   only through its eyes, never its own body. At T = {SINK_T} the stone at
   about ({SINK_AT[0]}, {SINK_AT[1]}) sinks: the actor looks around and
   plans again.
   Written by scripts/stepping_stones.py --walker.
     lmfilm run scenes/actors/walker_stones.lm --inset 0 -o renders/walker_stones */
Camera_AnimationParameters
pref_pos_x1_x2_y1_y2 0 640 0 360
observer 0.5 5.5 -8.5
lookatPoint 0 0 0.6
viewAngle 450
t_final_interval 42.0 0.04

Options
NBR_actors 1
iVisionWinSize 0 96 8
actorNbr_automata 0 walk_stepworthy init 10 -6.425 6.375 0.05 obs {START[0]} 1.6 {START[1]} lat 0 0 0 fov 900 vision_range 0.2 12 3 goal -2.5 0 3.5 goal 3.1 0 0.6 speed 1.0 size_actor 0.35 foothold_plane 0 foothold_step 0.5 0.25 foothold_map 10 12 0.24
actorNbr_automata 0 watch

Axiom
{SET}/* the actor: a person, its eyes at the actor's */
[ M () (7) () (0) m () (14) D () (50) () () (0) () (1) ]
"""
else:
    HEADER = f"""/* Walking on sparse foothold locations (thesis 5.9, 7.3.2):
   walk_stepworthy. A cube-like actor with a periscope eye crosses a field
   of {len(stones)} stepping stones (0.3 x 0.3, the size of a foot, tops
   at y = 0, {SPACING} apart on a jittered grid with gaps) standing in
   water {DEPTH} below, to two destinations in turn. It knows the stones
   only through its vision (a 96 x 96 window, 90 degrees) and its visual
   memory (voxels of 0.05, the stones' tops in the middle of a voxel
   layer; it forgets what it no longer sees within 3 m): it looks around, extracts the local map of
   the foothold locations from its memory (5.9.2), plans its steps by
   Dijkstra over walking states with the thesis's cost (eq. 7.3.1,
   p0 = n0 = p1 = n1 = 1, p2 = 5, n2 = 2) and walks them one by one. At
   T = {SINK_T} the stone at about ({SINK_AT[0]}, {SINK_AT[1]}) sinks; when
   the actor's memory forgets it, the planned path has an obstacle and
   the actor looks around and plans again. Turtle 1 colours it: white on
   the right foot, yellow on the left, red turning on the spot; the
   footholds it plans to step on are drawn as small spheres (for the
   viewer only).
   Written by scripts/stepping_stones.py.
     lmfilm run scenes/actors/footholds.lm --inset 0 -o renders/footholds
     lmfilm trace scenes/actors/footholds.lm   (the walk: "footing") */
Camera_AnimationParameters
pref_pos_x1_x2_y1_y2 0 640 0 360
observer 0.3 4.4 -7.6
lookatPoint 0 -0.6 1.2
viewAngle 500
t_final_interval 24.0 0.04

Options
NBR_actors 1
iVisionWinSize 0 96 8
actorNbr_automata 0 walk_stepworthy init 10 -6.425 6.375 0.05 obs -3.1 0.7 -3.4 lat 0 0 0 fov 900 vision_range 0.75 12 3 goal -2.5 0 3.5 goal 3.1 0 0.6 speed 1.2 size_actor 0.35 foothold_plane 0 turtle 1 mem_displ_cubes
actorNbr_automata 0 watch

Axiom
{SET}/* the actor: a cube with a periscope eye (turtle 1: H its heading, L up),
   all of it within its near plane (0.75) so that it never sees itself */
[ M () (7) () (0)
  [ a () () () () (0.12) ]
  [ f () () () (3) (0) (0.35_) (0) + () () () () (90) O () () () () (0.3) (0.02) (0.02) ]
  [ f () () () (3) (0.175_) (0.525_) (0) c () () () () (0.35) (0.35) (0.35) ]
  [ f () () () (3) (0.175) (0.55_) (0) c () () () () (0.04) (0.08) (0.2) ] ]
/* the stepping stones */"""
print(HEADER + ("/* the stepping stones */" if WALKER else ""))
for x, z in stones:
    y = f"T {SINK_T} - 1.5 / ?08 1.5 * {BASE} + _" if sinking(x, z) else f"{BASE}_"
    print(f"[ m () (16) $ () () (3) f () () () (2) ({x}{'_' if x < 0 else ''}) ({y}) ({z}{'_' if z < 0 else ''}) + () () () () (90) c () () () () ({BASE}) ({2 * HALF}) ({2 * HALF}) ]".replace("(-", "("))
print("""
Productions
EndProductions""")
