"""No import cycle between vlm_bench's modules, inside a package or across packages.

Every import statement counts: at module level, inside a function (a lazy import still makes
the importer depend on what it imports, and only defers the failure a cycle causes) and under
``if TYPE_CHECKING:`` (the types a module's signatures name are part of what it depends on).
The graph is grimp's, the one import-linter checks the layer contracts on (docs/decisions.md).
"""

from __future__ import annotations

import graphlib
import itertools

import pytest


def import_graph(package: str) -> dict[str, set[str]]:
    """Each module of ``package`` with the modules of ``package`` it imports."""
    grimp = pytest.importorskip("grimp")
    graph = grimp.build_graph(package, cache_dir=None)
    return {m: set(graph.find_modules_directly_imported_by(m)) for m in graph.modules}


def import_cycles(imports: dict[str, set[str]]) -> list[list[str]]:
    """Cycles of an import graph, ``[a, b, ..., a]`` with each module importing the next,
    found one at a time: each found cycle's first import is set aside before looking again (a
    further cycle through that import is not listed), so the list is empty exactly when the
    graph has no cycle."""
    left = {m: set(targets) for m, targets in imports.items()}
    cycles: list[list[str]] = []
    while True:
        try:
            # graphlib reads the mapping as node -> predecessors and reports a cycle by
            # following successors: each module in it is imported by the one after it.
            graphlib.TopologicalSorter(left).prepare()
        except graphlib.CycleError as exc:
            cycle = list(reversed(exc.args[1]))
            cycles.append(cycle)
            left[cycle[0]].discard(cycle[1])
            continue
        return cycles


def test_the_cycle_finder_finds_each_cycle_once_in_import_order() -> None:
    imports = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"e"}, "e": {"d"}, "f": {"a"}}
    cycles = import_cycles(imports)
    assert len(cycles) == 2
    for cycle in cycles:
        assert cycle[0] == cycle[-1]
        assert all(after in imports[before] for before, after in itertools.pairwise(cycle))
    assert import_cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


def test_no_import_cycle_in_the_package() -> None:
    cycles = import_cycles(import_graph("vlm_bench"))
    assert not cycles, "import cycles:\n" + "\n".join(" -> ".join(c) for c in cycles)
