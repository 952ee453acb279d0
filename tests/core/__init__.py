"""Tests of the core engine (System, joints, Kane's method, EquationsOfMotion)."""
