"""Celestial bodies as the renderer draws them: the Sun's limb-darkened disk."""
