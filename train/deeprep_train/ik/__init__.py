"""Inverse kinematics with RC-FK output heads (thesis Sec. 5.3.1, Table 5.1)."""
