"""Validation data for the project's own claims, made independently of the code under test."""
