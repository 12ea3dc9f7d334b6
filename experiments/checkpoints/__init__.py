"""This folder is also the data package ``ocplus_plan.data.checkpoints``: pyproject.toml maps it there, so a
wheel ships it; read it with ``ocplus_plan.data.data_files("checkpoints")``."""
