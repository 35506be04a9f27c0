"""Policy trees: a policy unrolled from a state to a depth, for the refinement engine.

Each inner node carries the policy's ground action; its edges are the action's joint
outcomes in the order of ``model.actions[a].outcomes(state)`` (so ``TreeEdge.outcome``
indexes that tuple) with float probabilities. Leaves are ``"goal"``, ``"horizon"``
(depth reached) or ``"dead_end"`` (no applicable action, or giving up is best).
Identical (state, depth) subtrees are shared, so memory stays proportional to the policy
graph even though root-to-leaf paths multiply.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterator

from stampc.ir.grounded import GroundModel
from stampc.solvers.solution import Solution


@dataclass(frozen=True)
class TreeEdge:
    probability: float
    outcome: int
    child: "TreeNode"


@dataclass(frozen=True)
class TreeNode:
    state: int
    depth: int
    action: int | None
    leaf: str | None
    children: tuple[TreeEdge, ...] = ()


def _leaf_kind(model: GroundModel, solution: Solution, state: int, depth: int,
               max_depth: int, planned_only: bool) -> tuple[str | None, int | None]:
    if model.is_goal(state):
        return "goal", None
    if depth >= max_depth or (solution.horizon is not None and depth >= solution.horizon):
        return "horizon", None
    if planned_only and not solution.planned(state, depth):
        return "horizon", None  # the solve never got here: plan it when it matters
    action = solution.action(state, depth)
    if action is None:
        return "dead_end", None
    return None, action


def policy_tree(model: GroundModel, solution: Solution, *, init: int | None = None,
                depth: int, planned_only: bool = False) -> TreeNode:
    """Unroll ``solution``'s policy from ``init`` (default ``solution.init``) to ``depth``.

    By default a state the solve never expanded gets a one-step lookahead action. With
    ``planned_only`` (a solve cut off by its time limit) such a state becomes a
    ``horizon`` leaf instead: expanding every tip of a large partial policy one by one
    can cost more than the solve itself."""
    root_state = solution.init if init is None else init
    memo: dict[tuple[int, int], TreeNode] = {}
    # Iterative post-order construction (no recursion limit on deep trees).
    stack: list[tuple[int, int, bool]] = [(root_state, 0, False)]
    pending: dict[tuple[int, int], tuple[int, tuple]] = {}
    while stack:
        state, d, ready = stack.pop()
        key = (state, d)
        if key in memo:
            continue
        if ready:
            action, outcomes = pending.pop(key)
            edges = tuple(TreeEdge(float(o.probability), i, memo[(o.apply(state), d + 1)])
                          for i, o in enumerate(outcomes))
            memo[key] = TreeNode(state, d, action, None, edges)
            continue
        leaf, action = _leaf_kind(model, solution, state, d, depth, planned_only)
        if leaf is not None:
            memo[key] = TreeNode(state, d, None, leaf)
            continue
        if key in pending:
            continue
        outcomes = model.actions[action].outcomes(state)
        pending[key] = (action, outcomes)
        stack.append((state, d, True))
        for o in outcomes:
            child = (o.apply(state), d + 1)
            if child not in memo:
                stack.append((child[0], child[1], False))
    return memo[(root_state, 0)]


def iter_paths(root: TreeNode) -> Iterator[tuple[float, tuple[TreeNode, ...]]]:
    """(path probability, nodes root..leaf) for every root-to-leaf path; the
    probabilities sum to 1."""
    stack: list[tuple[TreeNode, float, tuple[TreeNode, ...]]] = [(root, 1.0, (root,))]
    while stack:
        node, prob, path = stack.pop()
        if not node.children:
            yield prob, path
            continue
        for edge in reversed(node.children):
            stack.append((edge.child, prob * edge.probability, path + (edge.child,)))


def count_leaves(root: TreeNode) -> dict[str, float]:
    """Probability mass per leaf kind (``goal`` / ``horizon`` / ``dead_end``)."""
    mass: dict[str, float] = {}
    for prob, path in iter_paths(root):
        kind = path[-1].leaf or "dead_end"
        mass[kind] = mass.get(kind, 0.0) + prob
    return mass
