#!/usr/bin/env python3
"""Writes scenes/mocap/wave.bvh: a small Biovision BVH file whose pose is
known at every frame, for the motion-capture reader's tests. A root
(Hips, 6 channels) walks 0.5 m along x per second and turns about y; a
spine, a right arm (RightArm at the shoulder, RightForeArm at the elbow,
RightHand at the wrist, the hand's tip as its End Site: the joint names
of the CMU library) and a head. The figure faces +z, its right arm
stretches along -x at rest. At frame k (30 frames, 1/30 s apart):

  Hips      position (0.5 k/30, 1, 0), Yrotation 3k degrees
  RightArm      Zrotation 3k, Xrotation k      (channels listed Z then X)
  RightForeArm  Zrotation 2k
  other joints at rest (0)

Offsets in metres: Spine (0, 0.2, 0) from the hips, RightArm (-0.2, 0.3, 0)
from the spine, RightForeArm (-0.3, 0, 0), RightHand (-0.25, 0, 0), hand tip
(-0.1, 0, 0), Neck (0, 0.3, 0) from the spine, head top (0, 0.2, 0).

  python3 scripts/make_mocap.py scenes/mocap/wave.bvh"""
import sys

HIERARCHY = """HIERARCHY
ROOT Hips
{
  OFFSET 0.0 0.0 0.0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Spine
  {
    OFFSET 0.0 0.2 0.0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT RightArm
    {
      OFFSET -0.2 0.3 0.0
      CHANNELS 2 Zrotation Xrotation
      JOINT RightForeArm
      {
        OFFSET -0.3 0.0 0.0
        CHANNELS 1 Zrotation
        JOINT RightHand
        {
          OFFSET -0.25 0.0 0.0
          CHANNELS 3 Zrotation Xrotation Yrotation
          End Site
          {
            OFFSET -0.1 0.0 0.0
          }
        }
      }
    }
    JOINT Neck
    {
      OFFSET 0.0 0.3 0.0
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {
        OFFSET 0.0 0.2 0.0
      }
    }
  }
}
"""


def main():
    frames = 30
    rows = []
    for k in range(frames):
        hips = [0.5 * k / 30, 1.0, 0.0, 0.0, 0.0, 3.0 * k]
        spine = [0.0, 0.0, 0.0]
        shoulder = [3.0 * k, 1.0 * k]
        elbow = [2.0 * k]
        wrist = [0.0, 0.0, 0.0]
        neck = [0.0, 0.0, 0.0]
        values = hips + spine + shoulder + elbow + wrist + neck
        rows.append(' '.join(f'{v:.6f}' for v in values))
    text = HIERARCHY + f'MOTION\nFrames: {frames}\nFrame Time: {1 / 30:.8f}\n' + '\n'.join(rows) + '\n'
    with open(sys.argv[1], 'w') as f:
        f.write(text)


if __name__ == '__main__':
    main()
