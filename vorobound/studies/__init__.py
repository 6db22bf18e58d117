"""Numerical studies beside the main bounds (Cheng, Dey and Shewchuk's constant)."""
