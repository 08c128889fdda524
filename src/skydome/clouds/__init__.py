"""Volumetric clouds: noise, weather maps, cloud types, the cloud layer."""
