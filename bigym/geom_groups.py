"""MuJoCo geom groups: who draws a geom and who collides with it.

Shared by props (which build geoms), the visual merge (which regroups them at model
build) and the cameras (which draw groups 0-2 only).
"""

GROUP_BOTH = 0  # drawn and colliding
GROUP_VISUAL = 2  # drawn only
GROUP_COLLISION = 3  # colliding only (hidden from the cameras)
GROUP_MERGED = 4  # visual primitives replaced by a merged mesh (hidden, no contact)
GROUP_BALLAST = 5  # hidden mass-only geoms that set a prop's weight
