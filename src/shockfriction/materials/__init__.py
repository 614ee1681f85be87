"""Material library: data files with sources, SCG strength, EOS, thermal data."""

from shockfriction.materials.library import Material, Parameter, get_material, material_names

__all__ = ["Material", "Parameter", "get_material", "material_names"]
