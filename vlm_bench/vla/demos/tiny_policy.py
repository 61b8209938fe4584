"""A tiny plain-torch policy trained on an exported demonstrations dataset, and its
evaluation through the closed loop (docs/demos.md#train-a-policy).

It shows the whole path, not a good policy: the state and low-resolution images of a
stored dataset (read back from disk by :class:`~vlm_bench.vla.demos.reader.DemoDataset`)
go through a small convolutional encoder per camera and an MLP to the 12-D action,
normalised by the dataset's statistics; a few Adam steps on CPU fit it; the fitted policy
then drives the ARM steps of an episode's GT plan (:func:`~vlm_bench.vla.run_closed_loop`
with :func:`~vlm_bench.vla.policy_skills`) and the execution's S_pos, S_arm, S_safe and
S_task are returned. Requires torch (the ``hf`` extra or any torch install).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from vlm_bench.errors import MissingExtraError
from vlm_bench.types.closed_loop import Feedback
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import VlaScores
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.vla.closed_loop import run_closed_loop
from vlm_bench.vla.demos.reader import DemoDataset
from vlm_bench.vla.hierarchical import policy_skills
from vlm_bench.vla.observation import VlaObservation


def _torch() -> Any:
    try:
        import torch
    except ImportError as err:
        raise MissingExtraError("torch", "hf") from err
    return torch


def _network(n_views: int, state_size: int, action_size: int) -> Any:
    torch = _torch()
    nn = torch.nn

    class TinyNet(nn.Module):  # type: ignore[misc, name-defined]
        """Per camera: two strided convolutions and a global mean; then an MLP with the state."""

        def __init__(self) -> None:
            super().__init__()
            self.encoders = nn.ModuleList(
                nn.Sequential(
                    nn.Conv2d(3, 8, 3, stride=2, padding=1),
                    nn.ReLU(),
                    nn.Conv2d(8, 16, 3, stride=2, padding=1),
                    nn.ReLU(),
                    nn.AdaptiveAvgPool2d(1),
                    nn.Flatten(),
                )
                for _ in range(n_views)
            )
            self.head = nn.Sequential(
                nn.Linear(16 * n_views + state_size, 64), nn.ReLU(), nn.Linear(64, action_size)
            )

        def forward(self, images: list[Any], state: Any) -> Any:
            feats = [enc(img) for enc, img in zip(self.encoders, images, strict=True)]
            return self.head(torch.cat([*feats, state], dim=1))

    return TinyNet()


@dataclass
class TinyPolicy:
    """A fitted policy; call it as a :class:`~vlm_bench.vla.hierarchical.Policy`."""

    net: Any
    views: tuple[str, ...]
    size: int
    stats: dict[str, NDArray[np.float32]]
    losses: list[float]
    """Training loss after every step."""

    def _images(self, images: list[NDArray[np.uint8]]) -> list[Any]:
        torch = _torch()
        out = []
        for batch in images:
            t = torch.from_numpy(np.ascontiguousarray(batch)).permute(0, 3, 1, 2).float() / 255.0
            out.append(torch.nn.functional.interpolate(t, size=(self.size, self.size)))
        return out

    def predict(self, images: list[NDArray[np.uint8]], states: NDArray[np.float32]) -> Any:
        """Normalised actions of a batch (images per view ``(n, h, w, 3)``, states ``(n, 15)``)."""
        torch = _torch()
        state = (states - self.stats["state_mean"]) / self.stats["state_std"]
        return self.net(self._images(images), torch.from_numpy(state.astype(np.float32)))

    def __call__(self, observation: VlaObservation, step: ArmStep) -> NDArray[np.float64]:
        torch = _torch()
        images = [observation.images[v][None] for v in self.views]
        state = observation.proprio.to_array()[None]
        with torch.no_grad():
            out = self.predict(images, state).numpy()[0]
        action: NDArray[np.float64] = out * self.stats["action_std"] + self.stats["action_mean"]
        return action


def _stats(dataset: DemoDataset) -> dict[str, NDArray[np.float32]]:
    raw = (dataset.root / "meta" / "stats.json").read_text()
    import json

    stats = json.loads(raw)

    def arr(name: str, key: str) -> NDArray[np.float32]:
        a = np.array(stats[name][key], dtype=np.float32)
        return np.maximum(a, 1e-3) if key == "std" else a

    return {
        "state_mean": arr("observation.state", "mean"),
        "state_std": arr("observation.state", "std"),
        "action_mean": arr("action", "mean"),
        "action_std": arr("action", "std"),
    }


def train_tiny_policy(
    dataset: DemoDataset,
    steps: int = 20,
    batch_size: int = 32,
    size: int = 32,
    seed: int = 0,
    lr: float = 1e-3,
) -> TinyPolicy:
    """Fit a :class:`TinyPolicy` on every frame of ``dataset`` for ``steps`` Adam steps."""
    torch = _torch()
    torch.manual_seed(seed)
    views = tuple(dataset.views)
    states, actions = [], []
    images: dict[str, list[NDArray[np.uint8]]] = {v: [] for v in views}
    for index in range(len(dataset)):
        stored = dataset.episode(index)
        states.append(stored.states)
        actions.append(stored.actions)
        for v in views:
            images[v].append(dataset.images(index, v))
    s, a = np.concatenate(states), np.concatenate(actions)
    frames = {v: np.concatenate(images[v]) for v in views}
    stats = _stats(dataset)
    target = torch.from_numpy(((a - stats["action_mean"]) / stats["action_std"]).astype(np.float32))
    net = _network(len(views), s.shape[1], a.shape[1])
    policy = TinyPolicy(net, views, size, stats, [])
    optim = torch.optim.Adam(net.parameters(), lr=lr)
    rng = np.random.default_rng(seed)
    for _ in range(steps):
        rows = rng.integers(0, len(s), size=batch_size)
        pred = policy.predict([frames[v][rows] for v in views], s[rows])
        loss = torch.nn.functional.mse_loss(pred, target[rows])
        optim.zero_grad()
        loss.backward()
        optim.step()
        policy.losses.append(float(loss.item()))
    net.eval()
    return policy


def evaluate_policy(
    policy: TinyPolicy, episode: Episode, max_steps: int = 40, render_size: int = 64
) -> VlaScores | None:
    """S_pos, S_arm, S_safe, S_task of the episode's GT plan with ``policy`` driving its ARM
    steps (each for at most ``max_steps`` control steps; no replans)."""

    def planner(now: Episode, feedback: Feedback | None) -> list[UavStep | ArmStep]:
        return list(episode.gt_plan) if feedback is None else []

    skills = policy_skills(policy, max_steps=max_steps, render_size=render_size, views=policy.views)
    result = run_closed_loop(episode, planner, arm_skills=skills, max_rounds=0)
    return result.results[0].scores
