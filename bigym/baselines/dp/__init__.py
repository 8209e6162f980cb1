"""Diffusion Policy: a denoising diffusion model over action chunks (Chi et al., 2023)."""
