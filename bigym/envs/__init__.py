"""The BiGym tasks, one module per family."""
