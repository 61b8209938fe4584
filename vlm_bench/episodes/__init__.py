"""Episodes: task × seed → layout, UAV start, lighting and the geometric GT plan."""

from vlm_bench.episodes.generate import make_episode

__all__ = ["make_episode"]
