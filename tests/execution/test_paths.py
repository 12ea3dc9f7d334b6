"""Paths: BFS distances, interaction spots, and conflict-free multi-agent reservations."""

from __future__ import annotations

import itertools

import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.execution.paths import (
    DistanceOracle,
    PathRequest,
    Reservations,
    check_paths,
    layout_connects,
    layout_schedule,
    one_lane,
    plan_paths,
    space_time_astar,
)
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action
from ocplus_plan.sim.queries import (
    direction,
    distances,
    interaction_spots,
    layout_at,
    switching_walks,
)


def kitchen(grid, spawns, preset="easy", **kw):
    m = {"name": "t", "game_map": grid, "max_n_agent": len(spawns),
         "agent_spawn_points": spawns}
    m.update(kw)
    rules = make_rules(preset, map=m, n_agents=len(spawns))
    return new_state(rules, 0)


# a 3x7 one-lane corridor: row 1 is the only floor
CORRIDOR = [[1, 3, 1, 6, 1, 5, 1], [7, 0, 0, 0, 0, 0, 1], [1, 1, 1, 1, 1, 1, 1]]
# a corridor with one side pocket at (2, 3)
POCKET = [[1, 3, 1, 6, 1, 5, 1], [7, 0, 0, 0, 0, 0, 1], [1, 1, 1, 0, 1, 1, 1],
          [1, 1, 1, 1, 1, 1, 1]]


def test_bfs_distances_and_spots():
    s = kitchen(CORRIDOR, [[1, 1]])
    geo = s.geo
    walk = geo.walkables[0]
    d = distances(geo.neighbors, walk, [geo.flat(1, 1)])
    assert d[geo.flat(1, 5)] == 4
    assert d[geo.flat(0, 0)] == -1  # a wall is never reached
    board = geo.flat(0, 3)
    assert interaction_spots(geo.neighbors, walk, board) == [geo.flat(1, 3)]
    d = distances(geo.neighbors, walk, [geo.flat(1, 1)], blocked=[geo.flat(1, 3)])
    assert d[geo.flat(1, 4)] == -1
    oracle = DistanceOracle(geo)
    assert oracle.to_station(0, board)[geo.flat(1, 1)] == 2
    assert oracle.to_station(0, board) is oracle.to_station(0, board)  # memoised
    with pytest.raises(ConfigError, match="outside"):
        distances(geo.neighbors, walk, [999])


def test_step_action_matches_simulator_moves():
    s = kitchen(CORRIDOR, [[1, 2]])
    geo = s.geo
    start = s.agent_pos[0]
    right = geo.flat(1, 3)
    assert direction(geo, start, right) == Action.RIGHT
    assert direction(geo, start, start) == Action.STAY
    transition(s, [direction(geo, start, right)])
    assert s.agent_pos[0] == right
    with pytest.raises(ConfigError, match="not adjacent"):
        direction(geo, start, geo.flat(1, 5))


def test_single_agent_shortest_path():
    s = kitchen(CORRIDOR, [[1, 1]])
    geo = s.geo
    req = PathRequest(0, geo.flat(1, 1), frozenset({geo.flat(1, 5)}))
    out = plan_paths(geo, [req], horizon=20)
    assert out[0].reached
    assert out[0].path == [geo.flat(1, c) for c in range(1, 6)]


def test_head_on_in_corridor_with_pocket_lets_one_pass():
    """Two agents must pass each other: the lower-priority one ducks into the pocket."""
    s = kitchen(POCKET, [[1, 1], [1, 5]])
    geo = s.geo
    a = PathRequest(0, geo.flat(1, 1), frozenset({geo.flat(1, 5)}))
    b = PathRequest(1, geo.flat(1, 5), frozenset({geo.flat(1, 1)}))
    out = plan_paths(geo, [a, b], horizon=30)
    assert out[0].reached
    assert check_paths({k: v.path for k, v in out.items()}) == []
    assert geo.flat(2, 3) in out[1].path  # it used the pocket
    # executed in the simulator, the paths produce no blocked move
    paths = {k: v.path for k, v in out.items()}
    length = max(len(p) for p in paths.values())
    for t in range(length - 1):
        acts = [direction(geo, paths[k][min(t, len(paths[k]) - 1)],
                            paths[k][min(t + 1, len(paths[k]) - 1)]) for k in (0, 1)]
        ev = transition(s, acts).events
        assert not [e for e in ev if e.kind == "move_blocked"]
    assert s.agent_pos == [geo.flat(1, 5), geo.flat(1, 1)] or out[1].reached is False


def test_lower_priority_agent_backs_away_in_one_lane_corridor():
    s = kitchen(CORRIDOR, [[1, 2], [1, 4]])
    geo = s.geo
    a = PathRequest(0, geo.flat(1, 2), frozenset({geo.flat(1, 4)}))
    b = PathRequest(1, geo.flat(1, 4), frozenset())  # idle: just keep out of the way
    out = plan_paths(geo, [a, b], horizon=15)
    assert out[0].reached and out[0].path[-1] == geo.flat(1, 4)
    assert check_paths({k: v.path for k, v in out.items()}) == []
    assert out[1].path[-1] == geo.flat(1, 5)


def test_unreachable_goal_gives_safe_evasion_path():
    s = kitchen(CORRIDOR, [[1, 2], [1, 4]])
    geo = s.geo
    # agent 1 (high priority) parks on (1,3); agent 0 wants (1,5): impossible to pass
    a = PathRequest(1, geo.flat(1, 4), frozenset({geo.flat(1, 3)}))
    b = PathRequest(0, geo.flat(1, 2), frozenset({geo.flat(1, 5)}))
    out = plan_paths(geo, [a, b], horizon=10)
    assert out[1].reached
    assert not out[0].reached
    assert check_paths({k: v.path for k, v in out.items()}) == []


def test_static_others_are_obstacles():
    s = kitchen(POCKET, [[1, 1]])
    geo = s.geo
    req = PathRequest(0, geo.flat(1, 1), frozenset({geo.flat(1, 5)}))
    out = plan_paths(geo, [req], others={9: geo.flat(1, 3)}, horizon=20)
    assert not out[0].reached
    assert geo.flat(1, 3) not in out[0].path
    assert check_paths({0: out[0].path}, {9: geo.flat(1, 3)}) == []


def test_three_agents_random_goals_never_conflict():
    """Property-style: on an open kitchen, every prioritised plan is conflict-free."""
    s = kitchen([[1, 1, 3, 1, 4, 1, 1], [1, 0, 0, 0, 0, 0, 6], [5, 0, 0, 0, 0, 0, 1],
                 [1, 0, 0, 0, 0, 0, 6], [1, 1, 7, 1, 8, 1, 1]], [[1, 1], [3, 5], [2, 3]])
    geo = s.geo
    floor = [c for c in range(geo.rows * geo.cols) if geo.walkables[0][c]]
    count = 0
    for starts in itertools.islice(itertools.permutations(floor, 3), 0, 3000, 97):
        goals = [floor[(floor.index(x) * 7 + 3) % len(floor)] for x in starts]
        reqs = [PathRequest(i, st, frozenset({g})) for i, (st, g) in enumerate(zip(starts, goals))]
        out = plan_paths(geo, reqs, horizon=25)
        assert check_paths({k: v.path for k, v in out.items()}) == []
        count += 1
    assert count > 20


def test_reservations_forbid_swaps():
    res = Reservations(5)
    res.add_path(0, [1, 2])
    assert not res.can_move(2, 1, 0)  # the swap
    assert res.can_move(3, 1, 0)  # following into a cell being left is allowed
    assert not res.free(2, 3)  # parked


def test_bad_requests_raise():
    s = kitchen(CORRIDOR, [[1, 1]])
    geo = s.geo
    req = PathRequest(0, geo.flat(1, 1), frozenset())
    with pytest.raises(ConfigError, match="same cell"):
        plan_paths(geo, [req, PathRequest(1, geo.flat(1, 1), frozenset())])
    with pytest.raises(ConfigError, match="horizon"):
        plan_paths(geo, [req], horizon=0)


def test_layout_schedule_anticipates_switch():
    rules = make_rules("hard", map="hard_switch")
    s = new_state(rules, 0)
    geo = s.geo
    now = layout_schedule(s, anticipate=False)
    ahead = layout_schedule(s, anticipate=True)
    due = s.next_switch - s.t
    assert now(due + 1) is geo.walkables[0]
    assert ahead(due - 1) is geo.walkables[0]
    assert ahead(due) is geo.walkables[1]
    assert ahead(due + rules.map_switch_step) is geo.walkables[0]
    # the bottom wall (column 5, rows 4-5) closes at the switch: a path along row 5 that
    # would cross it after the switch goes round through row 3 instead
    s.next_switch = s.t + 3
    ahead = layout_schedule(s, anticipate=True)
    start, goal = geo.flat(5, 1), geo.flat(5, 6)
    naive = space_time_astar(geo, now, PathRequest(0, start, frozenset({goal})), Reservations(40))
    assert len(naive.path) - 1 == 5 and geo.flat(5, 5) in naive.path
    plan = space_time_astar(geo, ahead, PathRequest(0, start, frozenset({goal})), Reservations(40))
    assert plan.reached
    for t, c in enumerate(plan.path):
        assert ahead(t)[c], (t, geo.rc(c))
    assert geo.flat(5, 5) not in plan.path[3:] and geo.flat(4, 5) not in plan.path[3:]


def test_corridor3_three_agents_shift_without_conflict():
    rules = make_rules("easy", map="corridor3", n_agents=3)
    s = new_state(rules, 0)
    geo = s.geo
    # the rightmost agent wants the left end of its reach; the others must shift left
    reqs = [PathRequest(2, s.agent_pos[2], frozenset({geo.flat(1, 3)})),
            PathRequest(1, s.agent_pos[1], frozenset()),
            PathRequest(0, s.agent_pos[0], frozenset())]
    out = plan_paths(geo, reqs, horizon=20)
    assert out[2].reached
    paths = {k: v.path for k, v in out.items()}
    assert check_paths(paths) == []
    length = max(len(p) for p in paths.values())
    for t in range(length - 1):
        acts = [direction(geo, paths[k][min(t, len(paths[k]) - 1)],
                            paths[k][min(t + 1, len(paths[k]) - 1)]) for k in range(3)]
        ev = transition(s, acts).events
        assert not [e for e in ev if e.kind == "move_blocked"], (t, s.describe())
    assert s.agent_pos[2] == geo.flat(1, 3)


def test_layout_connects_says_whether_the_cooks_reach_every_station():
    """MapC: one cook never reaches every station in one layout; two cooks, one on each
    side, do; a small open kitchen always does."""
    one = new_state(make_rules("hard", n_agents=1), 0)
    two = new_state(make_rules("hard", n_agents=2), 0)
    assert not any(layout_connects(one.geo, k, one.agent_pos) for k in range(2))
    assert all(layout_connects(two.geo, k, two.agent_pos) for k in range(2))
    easy = new_state(make_rules("easy", n_agents=1), 0)
    assert layout_connects(easy.geo, 0, easy.agent_pos)


# two rooms joined by a cell that is a wall in the first layout and floor in the second:
# tomato (0,1) and window (1,0) on the left, board (0,5) and plates (2,6) on the right
SWITCHING = {
    "name": "t", "max_n_agent": 2, "agent_spawn_points": [[1, 1], [2, 5]],
    "game_map": [[1, 3, 1, 1, 1, 6, 1], [7, 0, 0, -1, 0, 0, 1], [1, 0, 0, 1, 0, 0, 5],
                 [1, 1, 1, 1, 1, 1, 1]],
    "switch_map": [[1, 3, 1, 1, 1, 6, 1], [7, 0, 0, 0, 0, 0, 1], [1, 0, 0, 1, 0, 0, 5],
                   [1, 1, 1, 1, 1, 1, 1]],
    "is_dynamic_map": True, "map_switch_step": 10,
}


def test_layout_at_follows_the_switch_schedule():
    assert [layout_at(0, 3, 5, t) for t in range(14)] == [0] * 3 + [1] * 5 + [0] * 5 + [1]
    assert layout_at(1, 0, 5, 0) == 0  # a switch due now is in force from now


def test_switching_walks_wait_for_the_switch_that_opens_the_way():
    s = new_state(make_rules("easy", map=SWITCHING, n_agents=2, dynamic=True), 0)
    geo = s.geo
    walks = switching_walks(geo, 10)
    start, board, spot = geo.flat(1, 1), geo.flat(0, 5), geo.flat(1, 5)
    # closed for 10 steps: one step to the wall, wait, then three through the opened cell
    assert walks.arrival(start, board, 0, 10) == (13, spot)
    assert walks.arrival(start, board, 1, 10) == (4, spot)  # open now: the plain walk
    assert walks.arrival(start, board, 1, 2) == (4, spot)  # it closes behind the cook
    # open for one more step only: the cook is cut off after (1,2) until it reopens
    assert walks.arrival(start, board, 1, 1) == (1 + 10 + 3, spot)
    assert walks.arrival(start, geo.flat(3, 3), 0, 10) is None  # no floor next to it ever
    assert switching_walks(geo, 10) is walks  # one per geometry and period
    # the phase some steps later: (layout, steps to its next switch)
    assert [walks.phase(0, 3, at) for at in (0, 2, 3, 12, 13)] == [(0, 3), (0, 1), (1, 10),
                                                                    (1, 1), (0, 10)]


def test_a_cook_that_cannot_reach_its_goal_yet_walks_towards_it_at_once():
    """Agent 1 parks on (1,4); agent 0 wants that cell too: it cannot get there inside the
    window, so it comes as close as it can, and starts now (a path that waits first and
    walks at the window's end is replanned every step and never leaves)."""
    s = kitchen(CORRIDOR, [[1, 1], [1, 5]])
    geo = s.geo
    a = PathRequest(1, geo.flat(1, 5), frozenset({geo.flat(1, 4)}))
    b = PathRequest(0, geo.flat(1, 1), frozenset({geo.flat(1, 4)}))
    out = plan_paths(geo, [a, b], horizon=20)
    assert out[1].reached and not out[0].reached
    assert out[0].path == [geo.flat(1, 1), geo.flat(1, 2), geo.flat(1, 3)]
    assert check_paths({k: v.path for k, v in out.items()}) == []


# a U: two arms joined by the top row, a counter between the arms
U_LANE = [[1, 3, 1, 6, 1], [1, 0, 0, 0, 1], [1, 0, 1, 0, 1], [7, 0, 1, 0, 5],
          [1, 1, 1, 1, 1]]
# the same U closed at the bottom: a loop
RING = [[1, 3, 1, 6, 1], [1, 0, 0, 0, 1], [1, 0, 1, 0, 1], [7, 0, 0, 0, 5],
        [1, 1, 1, 1, 1]]


@pytest.mark.parametrize("grid, spawns, lane", [
    (CORRIDOR, [[1, 1], [1, 4]], True),  # a straight lane
    (U_LANE, [[3, 1], [3, 3]], True),  # a bent one: still nobody passes anybody
    (POCKET, [[1, 1], [1, 4]], False),  # a side pocket to step into
    (RING, [[3, 1], [3, 3]], False),  # a loop: the cooks go round each other
    (CORRIDOR, [[1, 1]], True),
])
def test_one_lane_floors(grid, spawns, lane):
    s = kitchen(grid, spawns)
    cells = [s.agent_pos[a] for a in range(s.n_agents)]
    assert one_lane(s.geo, s.geo.walkables[0], cells) is lane
