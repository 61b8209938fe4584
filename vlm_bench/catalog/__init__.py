"""Loads and validates the shipped data files (world, tasks, skills, materialised GT)."""
