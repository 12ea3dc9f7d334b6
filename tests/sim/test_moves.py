"""Simultaneous moves (SPEC section 5): the outcome never depends on agent order."""

from __future__ import annotations

import itertools

import pytest

from ocplus_plan.sim.codes import Action

from .conftest import kitchen
from .helpers import kinds, run

R, D, L, U, S = (int(a) for a in (Action.RIGHT, Action.DOWN, Action.LEFT, Action.UP, Action.STAY))
OPEN = [
    [1, 3, 1, 6, 1, 1],
    [1, 0, 0, 0, 0, 1],
    [5, 0, 0, 0, 0, 7],
    [1, 0, 0, 0, 0, 1],
    [1, 1, 1, 1, 1, 1],
]


def outcome(roles):
    """roles: list of ((row, col), action). Run one step under every assignment of roles
    to agent indices; return the final cell of each role (identical for all orders)."""
    results = set()
    n = len(roles)
    for perm in itertools.permutations(range(n)):
        spawns = [None] * n
        acts = [None] * n
        for role, agent in enumerate(perm):
            spawns[agent] = list(roles[role][0])
            acts[agent] = roles[role][1]
        spec_rules, s = kitchen(OPEN, spawns)
        run(s, acts)
        results.add(tuple(s.agent_rc(perm[role]) for role in range(n)))
    assert len(results) == 1, f"outcome depends on agent order: {results}"
    return results.pop()


def test_free_moves_happen():
    assert outcome([((1, 1), R), ((3, 4), L)]) == ((1, 2), (3, 3))


def test_a_contested_cell_leaves_both_in_place():
    assert outcome([((1, 1), R), ((1, 3), L)]) == ((1, 1), (1, 3))


def test_a_swap_leaves_both_in_place():
    assert outcome([((1, 1), R), ((1, 2), L)]) == ((1, 1), (1, 2))


def test_an_agent_follows_one_that_leaves():
    assert outcome([((1, 1), R), ((1, 2), R), ((1, 3), D)]) == ((1, 2), (1, 3), (2, 3))


def test_a_blocked_leader_blocks_its_followers():
    # the leader bumps the wall; the chain behind it cannot move into held cells
    assert outcome([((1, 2), R), ((1, 3), R), ((1, 4), U)]) == ((1, 2), (1, 3), (1, 4))


def test_an_agent_that_stays_holds_its_cell():
    assert outcome([((2, 1), R), ((2, 2), S)]) == ((2, 1), (2, 2))


def test_a_rotation_cycle_blocks_everyone():
    roles = [((1, 1), R), ((1, 2), D), ((2, 2), L), ((2, 1), U)]
    assert outcome(roles) == ((1, 1), (1, 2), (2, 2), (2, 1))


def test_contest_and_follow_together():
    # A and B contest (2,2); C wants A's cell: A stays, so C stays too
    assert outcome([((2, 1), R), ((2, 3), L), ((3, 1), U)]) == ((2, 1), (2, 3), (3, 1))


def test_blocked_moves_are_reported_as_events():
    rules, s = kitchen(OPEN, [[1, 1], [1, 2]])
    ev, _ = run(s, [R, L])
    assert kinds(ev) == ["move_blocked", "move_blocked"] and {e.agent for e in ev} == {0, 1}


def test_bumping_a_wall_is_not_a_move():
    rules, s = kitchen(OPEN, [[1, 1]])
    ev, _ = run(s, U)  # the tomato tile: picks the tomato, does not move
    assert s.agent_rc(0) == (1, 1) and kinds(ev) == ["pickup"]


@pytest.mark.parametrize("bad", [[5], [-1], [0, 1]])
def test_invalid_actions_are_errors(bad):
    from ocplus_plan.errors import InvalidActionError

    rules, s = kitchen(OPEN, [[1, 1]])
    with pytest.raises(InvalidActionError):
        run(s, bad)
