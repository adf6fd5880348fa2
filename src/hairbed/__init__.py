"""hairbed: exact deformation of a dense bed of elastic hairs in channel flow."""

__all__: list[str] = []
__version__ = "0.1.0"
