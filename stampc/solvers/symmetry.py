"""Interchangeable objects: solving one state per orbit of object permutations.

A permutation σ of objects that maps the ground model onto itself — every action onto an
action with the same precondition and effects (facts renamed), the goal onto itself,
costs unchanged — is an automorphism of the SSP: ``V*(s) = V*(σ s)``, and a policy
optimal at ``σ s`` maps back to one optimal at ``s``. So the SSP can be solved over
orbit representatives only: every next state is replaced by its representative (same
value), outcomes that meet in one representative are merged. Values, bounds and
certificates are those of the full SSP (the representatives' Bellman equations are the
full ones with ``V(s') = V(rep s')``).

Found here: *classes* of objects of one type all of whose transpositions are
automorphisms (so every permutation is), and no fact mentions two objects of a class.
Then a state's per-object *signature* (which of its slot facts hold: ``status(p,
Queued)`` is slot ``status(_, Queued)`` of packet ``p``) determines it up to the class's
permutations, and the representative gives the sorted signatures to the objects in
order. Search-and-rescue's zones and schedule's packets are such classes (2^30
exploration patterns of 30 identical zones become 31 counts); on models without one
(blocksworld: ``on(a, b)`` mentions two blocks) detection gives up at the first check.
Models with derived facts are left alone.
"""

from __future__ import annotations

import time
from collections import Counter
from fractions import Fraction
from typing import Hashable

from stampc.ir.grounded import GAnd, GEffect, GFormula, GLit, GroundCondition, GroundModel
from stampc.ir.masks import indices

#: Detection stops after this long, keeping the classes completed (time, not safety).
MAX_SECONDS = 2.0
#: Models with more ground actions are not searched (rectangle-tireworld p11, 162,964
#: actions and 400 locations: 2 s without finding a class; its grounding takes 5-10 s).
MAX_ACTIONS = 100_000


class _Swap:
    """The fact permutation of one object transposition: pairs of slot facts swapped."""

    def __init__(self, pairs: list[tuple[int, int]]):
        self.map = {}
        for a, b in pairs:
            self.map[a], self.map[b] = b, a
        self.pairs = pairs

    def mask(self, m: int) -> int:
        for a, b in self.pairs:
            if ((m >> a) ^ (m >> b)) & 1:
                m ^= (1 << a) | (1 << b)
        return m

    def fact(self, f: int) -> int:
        return self.map.get(f, f)


def _multiset(items) -> frozenset:
    return frozenset(Counter(items).items())


def _formula_sig(f: GFormula, sw: _Swap | None) -> Hashable:
    if isinstance(f, GLit):
        return ("lit", sw.fact(f.fact) if sw else f.fact, f.positive)
    kind = "and" if isinstance(f, GAnd) else "or"
    return (kind, _multiset(_formula_sig(a, sw) for a in f.args))


def _cond_sig(c: GroundCondition, sw: _Swap | None) -> Hashable:
    pos, neg = int(c.pos), int(c.neg)
    if sw:
        pos, neg = sw.mask(pos), sw.mask(neg)
    return (pos, neg, _multiset(_formula_sig(f, sw) for f in c.rest), c.never)


def _effect_sig(e: GEffect, sw: _Swap | None) -> Hashable:
    add, delete, unknown = e.add, e.delete, e.unknown
    if sw:
        add, delete, unknown = sw.mask(add), sw.mask(delete), sw.mask(unknown)
    whens = _multiset((_cond_sig(c, sw), _effect_sig(sub, sw)) for c, sub in e.whens)
    blocks = _multiset(_multiset((Fraction(p), _effect_sig(sub, sw)) for p, sub in b.outcomes)
                       for b in e.blocks)
    return (add, delete, e.cost, unknown, whens, blocks)


class ObjectSymmetry:
    """Orbit representatives under the permutations of interchangeable object classes.

    ``slots[c][o]`` lists the fact indices of object ``o`` of class ``c``, one per slot
    (the same slot order for every object of the class)."""

    def __init__(self, classes: list[tuple[tuple[str, ...], list[list[int]]]]):
        self.classes = classes
        self._slots = [slots for _, slots in classes]
        self._masks = [sum(1 << f for row in slots for f in row) for slots in self._slots]
        #: fact -> (class, object) of every slot it fills (at(person, city) fills one
        #: of the person's and one of the city's)
        self._where: dict[int, list[tuple[int, int]]] = {}
        for c, slots in enumerate(self._slots):
            for o, row in enumerate(slots):
                for f in row:
                    self._where.setdefault(f, []).append((c, o))
        self._parent = -1  # the last parent given to successor() and its signatures
        self._parent_sigs: list[list[int] | None] = []
        self._parent_rep = False  # were all of the parent's signatures sorted?

    def __bool__(self) -> bool:
        return bool(self.classes)

    def _signatures(self, state: int, c: int) -> list[int]:
        sigs = []
        for row in self._slots[c]:
            sig = 0
            for r, f in enumerate(row):
                if (state >> f) & 1:
                    sig |= 1 << r
            sigs.append(sig)
        return sigs

    def _rebuild(self, state: int, c: int, sigs: list[int]) -> int:
        rebuilt = 0
        for row, sig in zip(self._slots[c], sorted(sigs)):
            r = 0
            while sig:
                if sig & 1:
                    rebuilt |= 1 << row[r]
                sig >>= 1
                r += 1
        return (state & ~self._masks[c]) | rebuilt

    def canonical(self, state: int) -> int:
        """The representative of ``state``'s orbit (the same for every state in it): each
        class's objects get the sorted signatures in order, so a state is its own
        representative exactly when its signatures are already sorted."""
        for c, mask in enumerate(self._masks):
            if state & mask:
                state = self._rebuild(state, c, self._signatures(state, c))
        return state

    def successor(self, parent: int, state: int) -> int:
        """``canonical(state)`` for a successor of ``parent``, without recomputing every
        signature: only the objects whose facts differ from ``parent``'s are re-read, and
        when ``parent``'s signatures were sorted and the changed ones keep them sorted,
        ``state`` is its own representative (boxworld: 750 successors per expansion);
        otherwise ``canonical(state)``."""
        if parent != self._parent:
            self._parent = parent
            self._parent_sigs = []
            for c in range(len(self._slots)):
                sigs = self._signatures(parent, c)
                self._parent_sigs.append(sigs if all(
                    a <= b for a, b in zip(sigs, sigs[1:])) else None)
            self._parent_rep = all(sigs is not None for sigs in self._parent_sigs)
        if not self._parent_rep:  # parent not a representative: the full computation
            return self.canonical(state)
        diff = parent ^ state
        touched: dict[int, list[int]] = {}
        where = self._where
        while diff:
            low = diff & -diff
            diff ^= low
            for c, o in where.get(low.bit_length() - 1, ()):
                touched.setdefault(c, []).append(o)
        for c, objects in touched.items():
            sigs = list(self._parent_sigs[c])
            row_of = self._slots[c]
            for o in objects:
                sig = 0
                for r, f in enumerate(row_of[o]):
                    if (state >> f) & 1:
                        sig |= 1 << r
                sigs[o] = sig
            last = len(sigs) - 1
            if any((o > 0 and sigs[o - 1] > sigs[o]) or (o < last and sigs[o] > sigs[o + 1])
                   for o in objects):
                # a permutation is needed; with several classes it moves the facts the
                # others' signatures read (at(person, city)): the full computation
                return self.canonical(state)
        return state

    def describe(self) -> list[str]:
        return [f"{len(objs)} interchangeable objects ({', '.join(objs[:3])}"
                f"{', ...' if len(objs) > 3 else ''}), {len(slots[0])} facts each"
                for objs, slots in self.classes]


def _object_slots(model: GroundModel, objects: list[str]):
    """Per object: slot template -> fact index, and the other objects of the list that
    share a fact with it (a template is a fact with the object's position blanked)."""
    members = set(objects)
    slots: dict[str, dict[tuple, int]] = {o: {} for o in objects}
    shared: dict[str, set[str]] = {o: set() for o in objects}
    for i, atom in enumerate(model.facts):
        hits = [k for k, a in enumerate(atom.args) if a in members]
        for k in hits:
            o = atom.args[k]
            slots[o][(atom.predicate, k, atom.args[:k] + atom.args[k + 1:])] = i
            # twice in one fact counts as sharing with itself: such objects stay alone
            shared[o].update(atom.args[j] for j in hits if j != k)
    return slots, shared


class _Index:
    """Which actions mention a fact or take an object as argument, built on first use
    (detection only looks at the actions a transposition can move)."""

    def __init__(self, model: GroundModel):
        self.model = model
        self.by_key = {(a.name, a.args): a.index for a in model.actions}
        self.own: dict[int, Hashable] = {}  # action index -> its signature, unrenamed
        self._by_fact: dict[int, list[int]] | None = None
        self._by_arg: dict[str, list[int]] = {}

    def moved(self, a: str, b: str, facts: list[int]) -> set[int]:
        if self._by_fact is None:
            self._by_fact = {}
            for action in self.model.actions:
                for f in _touched(action):
                    self._by_fact.setdefault(f, []).append(action.index)
                for x in set(action.args):
                    self._by_arg.setdefault(x, []).append(action.index)
        out = set(self._by_arg.get(a, ())) | set(self._by_arg.get(b, ()))
        for f in facts:
            out.update(self._by_fact.get(f, ()))
        return out

    def signature(self, j: int) -> Hashable:
        sig = self.own.get(j)
        if sig is None:
            other = self.model.actions[j]
            sig = self.own[j] = _action_sig(other, None)
        return sig


def _action_sig(action, sw: _Swap | None) -> Hashable:
    return (action.base_cost, action.delete_wins, _cond_sig(action.precondition, sw),
            _effect_sig(action.effect, sw))


def _transposition_ok(model: GroundModel, a: str, b: str, slots_a: list[int],
                      slots_b: list[int], index: _Index, deadline: float) -> bool:
    """Is swapping objects ``a`` and ``b`` an automorphism? Every action that takes one of
    them or mentions a swapped fact must map to an action with the renamed arguments and
    the same renamed precondition, effects and costs (the others map to themselves), and
    the goal must map to itself."""
    sw = _Swap(list(zip(slots_a, slots_b)))
    if _cond_sig(model.goal, sw) != _cond_sig(model.goal, None):
        return False
    for i in sorted(index.moved(a, b, slots_a + slots_b)):
        if time.perf_counter() > deadline:
            raise TimeoutError
        action = model.actions[i]
        args = tuple(b if x == a else a if x == b else x for x in action.args)
        j = index.by_key.get((action.name, args))
        if j is None or _action_sig(action, sw) != index.signature(j):
            return False
    return True


def _touched(action) -> set[int]:
    """Every fact the action's precondition or effect mentions."""
    facts: set[int] = set()

    def cond(c: GroundCondition) -> None:
        facts.update(indices(c.pos_facts))
        facts.update(indices(c.neg_facts))
        stack = list(c.rest)
        while stack:
            f = stack.pop()
            if isinstance(f, GLit):
                facts.add(f.fact)
            else:
                stack.extend(f.args)

    def eff(e: GEffect) -> None:
        facts.update(indices(e.add_facts))
        facts.update(indices(e.delete_facts))
        facts.update(indices(e.unknown_facts))
        for c, sub in e.whens:
            cond(c)
            eff(sub)
        for block in e.blocks:
            for _, sub in block.outcomes:
                eff(sub)

    cond(action.precondition)
    eff(action.effect)
    return facts


def find_symmetry(model: GroundModel, budget_s: float = MAX_SECONDS) -> ObjectSymmetry:
    """The interchangeable object classes of ``model`` (possibly none).

    Per type, objects are grouped by "their transposition is an automorphism" (an
    equivalence: (a c) = (a b)(b c)(a b)), each compared with the first member of the
    groups found so far; a pair that shares a fact, or whose slots differ, is not tried.
    Past ``budget_s`` seconds the search stops with the classes completed so far."""
    if model.axioms.rules or model.axioms.derived or len(model.actions) > MAX_ACTIONS:
        return ObjectSymmetry([])
    deadline = time.perf_counter() + budget_s
    by_type: dict[str, list[str]] = {}
    for name, typ in model.objects:
        by_type.setdefault(typ, []).append(name)
    index = _Index(model)
    if len(index.by_key) != len(model.actions):
        return ObjectSymmetry([])  # two actions with one name and arguments: no renaming
    classes = []
    for typ in sorted(by_type):
        objects = by_type[typ]
        if len(objects) < 2:
            continue
        slots, shared = _object_slots(model, objects)
        groups: list[list[str]] = []
        try:
            for o in objects:
                for group in groups:
                    first = group[0]
                    if (o in shared[first] or first in shared[first] or o in shared[o]
                            or not slots[o] or set(slots[o]) != set(slots[first])):
                        continue
                    keys = sorted(slots[first], key=repr)
                    if _transposition_ok(model, first, o, [slots[first][t] for t in keys],
                                         [slots[o][t] for t in keys], index, deadline):
                        group.append(o)
                        break
                else:
                    groups.append([o])
        except TimeoutError:
            break  # this type's groups are unfinished: keep only the classes before it
        for group in groups:
            if len(group) > 1:
                keys = sorted(slots[group[0]], key=repr)
                classes.append((tuple(group), [[slots[o][t] for t in keys] for o in group]))
    return ObjectSymmetry(classes)
