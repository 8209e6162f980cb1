"""What the offline-RL tests train on."""

TASK = "ReachTargetSingle"
DEMOS = 3
