"""Behaviour cloning with action chunks: an MLP from the observation to the next H actions."""
