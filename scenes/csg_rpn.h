// glint — the course's reverse-polish CSG text format (.csg) into a CsgTreeDesc.
//
// Format
// ------
// Line-oriented: one token-line per line. `#` starts a comment that runs to the end of the
// line; blank lines are ignored. Words are separated by spaces or tabs; keywords are lower
// case. Numbers are decimal (`1`, `-0.5`, `2e-3`) and must be finite as 32-bit floats.
//
// Operands push a primitive (a leaf) on the stack. The primitive's name comes first, then
// its keys in any order; every key is required and may be given only once (no defaults):
//   sphere   center X Y Z  radius R
//   box      min X Y Z  max X Y Z         min < max on every axis
//   cylinder radius R  height H           axis +Y, from y = 0 to y = H, always capped
//   cone     radius R  height H           base of radius R at y = 0, apex at y = H, capped
//   plane    point X Y Z  normal X Y Z    the solid half-space behind the normal (stored
//                                         normalized)
// Radius and height must be > 0, the plane normal must not be zero. Optional, anywhere
// among the keys:
//   material NAME                         one word; left in CsgNodeDesc::materialName for the
//                                         scene loader to resolve (at most once)
//   transform operations                  see below
//
// Operators pop the top of the stack (the right operand), then the one below it (the left
// operand), and push the node `left OP right` with children {left, right}:
//   union | intersection | difference     difference = left minus right
// An operator may be followed by transform operations that place the combined node; it takes
// no material (its leaves carry theirs).
//
// Transform operations build CsgNodeDesc::parentFromNode. They apply to the object in the
// order written, the first written first: `scale 2 2 2 translate 0 1 0` scales, then moves,
// i.e. parentFromNode = Tn * ... * T2 * T1.
//   translate X Y Z
//   rotate DEGREES AX AY AZ               right-handed, about the axis through the origin;
//                                         the axis must not be zero
//   scale SX SY SZ                        no factor may be zero
//   shear XY XZ YX YZ ZX ZY               x' = x + XY*y + XZ*z
//                                         y' = YX*x + y + YZ*z
//                                         z' = ZX*x + ZY*y + z
// The composed transform of a node must be finite and invertible.
//
// At the end of the file exactly one node must be left on the stack: the tree's root. The tree
// may be at most kMaxCsgDepth (1000) levels deep; a lone primitive is one level.
//
//   # a die: a rounded cube minus a pip
//   box min -1 -1 -1 max 1 1 1 material ivory
//   sphere center 0 0 0 radius 1.4
//   intersection
//   sphere center 0 1 0 radius 0.2 material ink
//   difference rotate 45 0 1 0
//
// Errors are SceneErrors located at "FILE:LINE" (the pointer is empty), e.g.
//   tree.csg:12: stack underflow: 'union' needs 2 operands, the stack holds 1
// for: stack underflow, operands left over at the end (how many, and the line of the first
// one), no operand at all, unknown words, missing or repeated keys, bad or non-finite
// numbers, too few numbers for a key, a tree deeper than the limit, and the value checks above.
#pragma once

#include <string>

#include "scenes/description.h"

namespace glint {

// Parses the text of a .csg file; `file` names it in messages and in every node's `where`
// ({file + ":" + line, ""}). Nodes come in the order their lines create them; leaves keep
// material = -1.
CsgTreeDesc parseCsgRpn(const std::string& text, const std::string& file);

// Reads the file at `path` (SceneError "PATH: cannot read file" when it cannot) and parses it.
CsgTreeDesc loadCsgRpn(const std::string& path);

}  // namespace glint
