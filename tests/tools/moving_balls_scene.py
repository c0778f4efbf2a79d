#!/usr/bin/env python3
"""A scene of 4,000 balls drifting without gravity over sectors of 8 (2 layers of 50 x 40, random velocities
up to 2 units/s, seed 1): every body moves, so a cluster's transport carries every body every frame.
Used to compare the DDS profiles side by side (docs/operations.md):

  python3 tests/tools/moving_balls_scene.py > /tmp/moving4000.textproto
  build/server/lpss-cluster /tmp/moving4000.textproto --workers 2 --frames 300 --domain 77
  build/server/lpss-cluster /tmp/moving4000.textproto --workers 2 --frames 300 --domain 77 \\
      --profile deploy/profiles/lpss-local-shm.xml
"""
import random

random.seed(1)
lines = ['sector_size: 8', 'dt: 0.016666666666666666', 'precision_radius: 1000',
         'gravity { x: 0 y: 0 z: 0 }', 'sleeping: false']
i = 0
for x in range(50):
    for y in range(40):
        for z in range(2):
            i += 1
            vx = random.uniform(-2, 2)
            vy = random.uniform(-2, 2)
            lines.append('bodies { id: %d name: "b%d" shape { sphere { radius: 0.4 } } mass: 1 '
                         'position { global { x: %g y: %g z: %g } } linear_velocity { x: %g y: %g } }'
                         % (i, i, x * 2.0, y * 2.0, z * 2.0, vx, vy))
print('\n'.join(lines))
