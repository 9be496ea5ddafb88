// The one-cell bounds of a square that lies inside one bicubic piece (a de Casteljau quadrant
// below a leaf), computed from its Bézier net as the planner needs them (docs/ADAPTIVE.md §3 with
// r = 0). Internal to the adaptive room.
#pragma once

#include "core/math/bezier_net.h"

namespace tessera {

// The (1, 1) grid's bound (SurfaceNode::pairBound for an exact piece): the pair through the
// corners, with the twist.
double exactPairBound(const BezierNet& net);
// What points on each side add to it (SurfaceNode::sideBow; needed only where the pair is within ε).
void exactSideBows(const BezierNet& net, double bows[4]);
// |f(½, ½) − L(½, ½)| for the bilinear L through the corners: the pair bound is at least this.
double centreGap(const BezierNet& net);

}  // namespace tessera
