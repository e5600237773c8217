"""What the parts share: a build123d ``BasePartObject`` with labelled children and joints.

Each part (:class:`~origami_cad.parts.TSAModule`, ``RingRail``, ``Blocker``,
``DriverAdapter``) builds its solids privately, as a labelled ``Compound`` tree in its
own frame, and hands it to :class:`OrigamiPart`, which

* applies ``align`` (the tree's bounding box) then ``rotation`` to the whole tree, so
  that every child, and every joint, moves with the part;
* adds the part to the active ``BuildPart`` in ``mode`` (build123d isolates what the
  part builds on the way: nothing but the finished part reaches the user's builder),
  placed at the builder's ``Locations``, its children and joints placed with it;
* attaches the part's named ``RigidJoint`` s;
* keeps its children where the part is when it is placed by ``locate``, ``move``,
  ``moved`` or a joint's ``connect_to`` (build123d moves a ``Compound``'s own shape
  only, leaving its children behind: the STEP would hold them where they were built).

Lengths are mm, angles degrees.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from build123d import Align, BasePartObject, Compound, Location, Mode, RigidJoint, Rotation

from origami_cad._args import Arg, brief_value
from origami_cad.errors import FabricationError
from origami_cad.fabrication.assembly import moved_tree

__all__ = ["OrigamiPart"]


def _placement(owner: str, rotation: Any, align: Any, mode: Any) -> tuple[Location, Any]:
    """``rotation`` (three angles, degrees, or a build123d ``Location``) and ``align`` (an
    ``Align`` or three of them, or None) checked; else a :class:`FabricationError` naming
    the argument and the value."""
    if isinstance(rotation, Location):
        rotate = rotation
    else:
        angles = Arg("floats", length=3, min=-1e4, max=1e4, optional=False).check(
            f"{owner}: rotation", rotation, FabricationError
        )
        rotate = Rotation(*angles)
    each = tuple(align) if isinstance(align, tuple | list) else (align,)
    if align is not None and (
        len(each) not in (1, 3) or not all(isinstance(a, Align | None) for a in each)
    ):
        raise FabricationError(
            f"{owner}: align: expected an Align or three of them (x, y, z), "
            f"got {brief_value(align)}"
        )
    Arg("object", types=(Mode,), optional=False).check(f"{owner}: mode", mode, FabricationError)
    return rotate, align


def _align_offset(tree: Compound, align: Any) -> Location:
    if align is None:
        return Location()
    aligns = tuple(align) if isinstance(align, tuple | list) else (align, align, align)
    return Location(tree.bounding_box().to_align_offset(aligns))


class OrigamiPart(BasePartObject):
    """A part of the library: a labelled tree of solids with named joints.

    Parameters
    ----------
    tree : Compound
        The part's solids as labelled, coloured children, in the part's frame (mm).
    joints : mapping of str to Location
        The part's joints (``RigidJoint``), in the part's frame.
    params : object
        The part's parameter dataclass (:attr:`params`).
    rotation : RotationLike
        Angles about x, y, z (degrees), applied after ``align``.
    align : Align or tuple of Align, optional
        Align the part's bounding box (MIN, CENTER, MAX per axis) on the origin.
    mode : Mode
        How the part combines with the active ``BuildPart`` (ADD, SUBTRACT...).
    """

    def __init__(
        self,
        tree: Compound,
        joints: Mapping[str, Location],
        params: Any,
        rotation: Any = (0, 0, 0),
        align: Align | tuple[Align, Align, Align] | None = None,
        mode: Mode = Mode.ADD,
    ):
        rotate, align = _placement(type(self).__name__, rotation, align, mode)
        frame = rotate * _align_offset(tree, align)
        placed = moved_tree(tree, frame)
        super().__init__(placed, mode=mode)
        self.rotation = rotate
        self.params = params
        for name, loc in joints.items():
            RigidJoint(name, self, frame * loc)

    @property
    def info(self) -> str:
        """What the part is: its label and volume (mm^3)."""
        return f"{self.label}: {self.volume:.1f} mm^3"

    def _carry_children(self, before: Location) -> None:
        """Move every node below the part as the part moved from ``before`` to now."""
        delta = self.location * before.inverse()
        if delta == Location():
            return
        stack = list(self.children)
        while stack:
            node = stack.pop()
            node.move(delta)  # an OrigamiPart below carries its own children
            if not isinstance(node, OrigamiPart):
                stack.extend(node.children)

    def _publish_to_context(self, object_scope: Any) -> None:
        """Publish to the user's builder, and place the children as the part was placed.

        Under several ``Locations`` (or a builder's several output placements) the part
        becomes one copy per placement, as build123d's own objects do: its shape a flat
        compound of every copy's solids (which the builder combines in ``mode``), its
        children one labelled tree per copy.
        """
        placements = [
            pub * out
            for pub in object_scope.publication_locations
            for out in object_scope.output_placements
        ]
        if len(placements) <= 1:
            before = self.location
            super()._publish_to_context(object_scope)
            self._carry_children(before)
            return
        trees = [moved_tree(child, loc) for loc in placements for child in self.children]
        solids = [loc * solid for loc in placements for solid in self.solids()]
        self.wrapped = Compound(solids).wrapped
        self.children = trees
        target = object_scope.publication_target
        if target is not None and self.mode != Mode.PRIVATE:
            target._add_to_context(self, mode=self.mode)

    def locate(self, loc: Location) -> OrigamiPart:
        """Place the part at ``loc`` (what ``connect_to`` does), its children with it."""
        before = self.location
        super().locate(loc)
        self._carry_children(before)
        return self

    def moved(self, loc: Location) -> OrigamiPart:
        """A copy moved by ``loc``, its children with it."""
        before = self.location
        out = super().moved(loc)
        out._carry_children(before)
        return out

    def move(self, loc: Location) -> OrigamiPart:
        """Move the part by ``loc`` in place, its children with it."""
        before = self.location
        super().move(loc)
        self._carry_children(before)
        return self
