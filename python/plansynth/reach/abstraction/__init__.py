"""Convex decomposition of the free space with region adjacency (Shoukry et al., CDC
2016, Section III, Algorithm 1 line 1: the discrete abstraction).

The workspace minus the obstacles is cut into convex regions with pairwise disjoint
interiors whose union is exactly the free space. Two regions are *adjacent* when they
share a boundary piece of positive (d-1)-measure; the SAT part of the planner walks
this graph. The decomposition is obstacle-based and coarse (not a grid): fewer regions
make the Boolean search smaller, so several constructions are tried and the one with
the fewest regions is kept (``method="auto"``):

``hertel-mehlhorn``  2-D: shapely's constrained Delaunay triangulation of the free
                     polygon, then Hertel-Mehlhorn removal of every diagonal whose two
                     sides stay convex (at most 4x the optimal number of pieces).
``slab-y``, ``slab-x`` 2-D: trapezoids between consecutive vertex coordinates along the
                     sweep axis, then greedy merging of neighbours whose union is convex.
``boxes``            2-D and 3-D when every obstacle is a box: the grid of all obstacle
                     coordinates, free cells grown greedily into maximal boxes (the
                     best of all axis orders).

Adjacency is never computed by floating-point geometry on the final regions: each
construction starts from elementary pieces whose contacts are known combinatorially
(triangles of one triangulation sharing an edge; trapezoids whose intervals on a common
sweep line overlap; grid cells sharing a face), merges only pieces whose union is
convex (checked with exact orientation predicates), and lifts piece contacts to regions.

One module per part:

``regions``          the values: :class:`Region` and :class:`Abstraction`;
``predicates``       exact orientation, collinearity and orientation of cycles;
``freespace``        the free space of a 2-D problem as polygons;
``pieces``           greedy convex merging of pieces with exact contacts;
``hertel_mehlhorn``, ``slabs``, ``boxes``   the constructions;
``outer``            outer polygons of finely sampled convex obstacles (coarsening);
``goal``             the regions that meet the goal;
``build``            :func:`abstract`, the front that runs and compares them.

>>> from plansynth.reach.families import maze
>>> a = abstract(maze(1))
>>> len(a.regions), a.adjacency, a.start_regions, a.goal_regions
(3, ((1,), (0, 2), (1,)), (0,), (2,))
"""

from plansynth.reach.abstraction.build import METHODS, abstract
from plansynth.reach.abstraction.outer import OUTER_VERTICES, outer_polygon
from plansynth.reach.abstraction.regions import Abstraction, Region

__all__ = ["Region", "Abstraction", "abstract", "METHODS", "outer_polygon", "OUTER_VERTICES"]
