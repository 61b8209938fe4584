"""Episodes: task × seed → layout, UAV start, lighting and the geometric GT plan."""

from vlm_bench.episodes.committed import get_episode
from vlm_bench.episodes.generate import make_episode

__all__ = ["get_episode", "make_episode"]
