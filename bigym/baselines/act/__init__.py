"""ACT: action chunking with transformers, a conditional VAE over chunks (Zhao et al., 2023)."""
