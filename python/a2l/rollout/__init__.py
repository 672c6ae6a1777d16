"""Rollouts in a scene: the effect tests (:mod:`a2l.rollout.effect_tests`), above the scenes
(:mod:`a2l.sim`) and below the rooms that run skills and acquisitions."""
