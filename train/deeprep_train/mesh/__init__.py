"""Meshes: the fully convolutional mesh autoencoder (thesis chapter 3)."""
