//! The libMeshb keyword table: code, name, whether a count follows the keyword, and the
//! layout of one item.
//!
//! Source: LoicMarechal/libMeshb `sources/libmeshb7.c` (`GmfKwdFmt`, libMeshb 7). The code
//! of a keyword is its position in the table; binary files store the code, ASCII files the
//! name. Layout letters: `i` an integer, `r` a real, `c` a string, `d<x>` one `<x>` per
//! space dimension, `s<x>` / `h<x>` one `<x>` per solution component (after the
//! solution-type header); `n` has no fixed size.

/// One keyword: name, whether a count follows it, layout of one item.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Keyword {
    pub name: &'static str,
    pub counted: bool,
    pub layout: &'static str,
}

const fn k(name: &'static str, counted: bool, layout: &'static str) -> Keyword {
    Keyword { name, counted, layout }
}

/// Every keyword, indexed by its code.
pub(crate) const KEYWORDS: [Keyword; 241] = [
    k("Reserved", false, ""),                                                                    // 0
    k("MeshVersionFormatted", false, "i"),                                                       // 1
    k("Reserved", false, ""),                                                                    // 2
    k("Dimension", false, "i"),                                                                  // 3
    k("Vertices", true, "dri"),                                                                  // 4
    k("Edges", true, "iii"),                                                                     // 5
    k("Triangles", true, "iiii"),                                                                // 6
    k("Quadrilaterals", true, "iiiii"),                                                          // 7
    k("Tetrahedra", true, "iiiii"),                                                              // 8
    k("Prisms", true, "iiiiiii"),                                                                // 9
    k("Hexahedra", true, "iiiiiiiii"),                                                           // 10
    k("Reserved", false, ""),                                                                    // 11
    k("Reserved", false, ""),                                                                    // 12
    k("Corners", true, "i"),                                                                     // 13
    k("Ridges", true, "i"),                                                                      // 14
    k("RequiredVertices", true, "i"),                                                            // 15
    k("RequiredEdges", true, "i"),                                                               // 16
    k("RequiredTriangles", true, "i"),                                                           // 17
    k("RequiredQuadrilaterals", true, "i"),                                                      // 18
    k("TangentAtEdgeVertices", true, "iii"),                                                     // 19
    k("NormalAtVertices", true, "ii"),                                                           // 20
    k("NormalAtTriangleVertices", true, "iii"),                                                  // 21
    k("NormalAtQuadrilateralVertices", true, "iiii"),                                            // 22
    k("AngleOfCornerBound", false, "r"),                                                         // 23
    k("TrianglesP2", true, "iiiiiii"),                                                           // 24
    k("EdgesP2", true, "iiii"),                                                                  // 25
    k("SolAtPyramids", true, "sr"),                                                              // 26
    k("QuadrilateralsQ2", true, "iiiiiiiiii"),                                                   // 27
    k("ISolAtPyramids", true, "iiiii"),                                                          // 28
    k("SubDomainFromGeom", true, "iii"),                                                         // 29
    k("TetrahedraP2", true, "iiiiiiiiiii"),                                                      // 30
    k("Fault_NearTri", true, "i"),                                                               // 31
    k("Fault_Inter", true, "i"),                                                                 // 32
    k("HexahedraQ2", true, "iiiiiiiiiiiiiiiiiiiiiiiiiiii"),                                      // 33
    k("ExtraVerticesAtEdges", true, "in"),                                                       // 34
    k("ExtraVerticesAtTriangles", true, "in"),                                                   // 35
    k("ExtraVerticesAtQuadrilaterals", true, "in"),                                              // 36
    k("ExtraVerticesAtTetrahedra", true, "in"),                                                  // 37
    k("ExtraVerticesAtPrisms", true, "in"),                                                      // 38
    k("ExtraVerticesAtHexahedra", true, "in"),                                                   // 39
    k("VerticesOnGeometricVertices", true, "ii"),                                                // 40
    k("VerticesOnGeometricEdges", true, "iirr"),                                                 // 41
    k("VerticesOnGeometricTriangles", true, "iirrr"),                                            // 42
    k("VerticesOnGeometricQuadrilaterals", true, "iirrr"),                                       // 43
    k("EdgesOnGeometricEdges", true, "ii"),                                                      // 44
    k("Fault_FreeEdge", true, "i"),                                                              // 45
    k("Polyhedra", true, "iiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiii"),                                   // 46
    k("Polygons", false, "iiiiiiiii"),                                                           // 47
    k("Fault_Overlap", true, "i"),                                                               // 48
    k("Pyramids", true, "iiiiii"),                                                               // 49
    k("BoundingBox", false, "drdr"),                                                             // 50
    k("Reserved", false, ""),                                                                    // 51
    k("PrivateTable", true, "i"),                                                                // 52
    k("Fault_BadShape", true, "i"),                                                              // 53
    k("End", false, ""),                                                                         // 54
    k("TrianglesOnGeometricTriangles", true, "ii"),                                              // 55
    k("TrianglesOnGeometricQuadrilaterals", true, "ii"),                                         // 56
    k("QuadrilateralsOnGeometricTriangles", true, "ii"),                                         // 57
    k("QuadrilateralsOnGeometricQuadrilaterals", true, "ii"),                                    // 58
    k("Tangents", true, "dr"),                                                                   // 59
    k("Normals", true, "dr"),                                                                    // 60
    k("TangentAtVertices", true, "ii"),                                                          // 61
    k("SolAtVertices", true, "sr"),                                                              // 62
    k("SolAtEdges", true, "sr"),                                                                 // 63
    k("SolAtTriangles", true, "sr"),                                                             // 64
    k("SolAtQuadrilaterals", true, "sr"),                                                        // 65
    k("SolAtTetrahedra", true, "sr"),                                                            // 66
    k("SolAtPrisms", true, "sr"),                                                                // 67
    k("SolAtHexahedra", true, "sr"),                                                             // 68
    k("DSolAtVertices", true, "sr"),                                                             // 69
    k("ISolAtVertices", true, "i"),                                                              // 70
    k("ISolAtEdges", true, "ii"),                                                                // 71
    k("ISolAtTriangles", true, "iii"),                                                           // 72
    k("ISolAtQuadrilaterals", true, "iiii"),                                                     // 73
    k("ISolAtTetrahedra", true, "iiii"),                                                         // 74
    k("ISolAtPrisms", true, "iiiiii"),                                                           // 75
    k("ISolAtHexahedra", true, "iiiiiiii"),                                                      // 76
    k("Iterations", false, "i"),                                                                 // 77
    k("Time", false, "r"),                                                                       // 78
    k("Fault_SmallTri", true, "i"),                                                              // 79
    k("CoarseHexahedra", true, "i"),                                                             // 80
    k("Comments", true, "c"),                                                                    // 81
    k("PeriodicVertices", true, "ii"),                                                           // 82
    k("PeriodicEdges", true, "ii"),                                                              // 83
    k("PeriodicTriangles", true, "ii"),                                                          // 84
    k("PeriodicQuadrilaterals", true, "ii"),                                                     // 85
    k("PrismsP2", true, "iiiiiiiiiiiiiiiiiii"),                                                  // 86
    k("PyramidsP2", true, "iiiiiiiiiiiiiii"),                                                    // 87
    k("QuadrilateralsQ3", true, "iiiiiiiiiiiiiiiii"),                                            // 88
    k("QuadrilateralsQ4", true, "iiiiiiiiiiiiiiiiiiiiiiiiii"),                                   // 89
    k("TrianglesP3", true, "iiiiiiiiiii"),                                                       // 90
    k("TrianglesP4", true, "iiiiiiiiiiiiiiii"),                                                  // 91
    k("EdgesP3", true, "iiiii"),                                                                 // 92
    k("EdgesP4", true, "iiiiii"),                                                                // 93
    k("IRefGroups", true, "ciii"),                                                               // 94
    k("DRefGroups", true, "iii"),                                                                // 95
    k("TetrahedraP3", true, "iiiiiiiiiiiiiiiiiiiii"),                                            // 96
    k("TetrahedraP4", true, "iiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiii"),                             // 97
    k("HexahedraQ3", true, "iiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiii"), // 98
    k(
        "HexahedraQ4",
        true,
        "iiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiii",
    ), // 99
    k("PyramidsP3", true, "iiiiiiiiiiiiiiiiiiiiiiiiiiiiiii"),                                    // 100
    k("PyramidsP4", true, "iiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiii"),           // 101
    k("PrismsP3", true, "iiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiii"),                            // 102
    k("PrismsP4", true, "iiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiiii"), // 103
    k("HOSolAtEdgesP1", true, "hr"),                                                             // 104
    k("HOSolAtEdgesP2", true, "hr"),                                                             // 105
    k("HOSolAtEdgesP3", true, "hr"),                                                             // 106
    k("HOSolAtTrianglesP1", true, "hr"),                                                         // 107
    k("HOSolAtTrianglesP2", true, "hr"),                                                         // 108
    k("HOSolAtTrianglesP3", true, "hr"),                                                         // 109
    k("HOSolAtQuadrilateralsQ1", true, "hr"),                                                    // 110
    k("HOSolAtQuadrilateralsQ2", true, "hr"),                                                    // 111
    k("HOSolAtQuadrilateralsQ3", true, "hr"),                                                    // 112
    k("HOSolAtTetrahedraP1", true, "hr"),                                                        // 113
    k("HOSolAtTetrahedraP2", true, "hr"),                                                        // 114
    k("HOSolAtTetrahedraP3", true, "hr"),                                                        // 115
    k("HOSolAtPyramidsP1", true, "hr"),                                                          // 116
    k("HOSolAtPyramidsP2", true, "hr"),                                                          // 117
    k("HOSolAtPyramidsP3", true, "hr"),                                                          // 118
    k("HOSolAtPrismsP1", true, "hr"),                                                            // 119
    k("HOSolAtPrismsP2", true, "hr"),                                                            // 120
    k("HOSolAtPrismsP3", true, "hr"),                                                            // 121
    k("HOSolAtHexahedraQ1", true, "hr"),                                                         // 122
    k("HOSolAtHexahedraQ2", true, "hr"),                                                         // 123
    k("HOSolAtHexahedraQ3", true, "hr"),                                                         // 124
    k("BezierBasis", false, "i"),                                                                // 125
    k("ByteFlow", true, "i"),                                                                    // 126
    k("EdgesP2Ordering", true, "i"),                                                             // 127
    k("EdgesP3Ordering", true, "i"),                                                             // 128
    k("TrianglesP2Ordering", true, "iii"),                                                       // 129
    k("TrianglesP3Ordering", true, "iii"),                                                       // 130
    k("QuadrilateralsQ2Ordering", true, "ii"),                                                   // 131
    k("QuadrilateralsQ3Ordering", true, "ii"),                                                   // 132
    k("TetrahedraP2Ordering", true, "iiii"),                                                     // 133
    k("TetrahedraP3Ordering", true, "iiii"),                                                     // 134
    k("PyramidsP2Ordering", true, "iii"),                                                        // 135
    k("PyramidsP3Ordering", true, "iii"),                                                        // 136
    k("PrismsP2Ordering", true, "iiii"),                                                         // 137
    k("PrismsP3Ordering", true, "iiii"),                                                         // 138
    k("HexahedraQ2Ordering", true, "iii"),                                                       // 139
    k("HexahedraQ3Ordering", true, "iii"),                                                       // 140
    k("EdgesP1Ordering", true, "i"),                                                             // 141
    k("EdgesP4Ordering", true, "i"),                                                             // 142
    k("TrianglesP1Ordering", true, "iii"),                                                       // 143
    k("TrianglesP4Ordering", true, "iii"),                                                       // 144
    k("QuadrilateralsQ1Ordering", true, "ii"),                                                   // 145
    k("QuadrilateralsQ4Ordering", true, "ii"),                                                   // 146
    k("TetrahedraP1Ordering", true, "iiii"),                                                     // 147
    k("TetrahedraP4Ordering", true, "iiii"),                                                     // 148
    k("PyramidsP1Ordering", true, "iii"),                                                        // 149
    k("PyramidsP4Ordering", true, "iii"),                                                        // 150
    k("PrismsP1Ordering", true, "iiii"),                                                         // 151
    k("PrismsP4Ordering", true, "iiii"),                                                         // 152
    k("HexahedraQ1Ordering", true, "iii"),                                                       // 153
    k("HexahedraQ4Ordering", true, "iii"),                                                       // 154
    k("FloatingPointPrecision", false, "i"),                                                     // 155
    k("HOSolAtEdgesP4", true, "hr"),                                                             // 156
    k("HOSolAtTrianglesP4", true, "hr"),                                                         // 157
    k("HOSolAtQuadrilateralsQ4", true, "hr"),                                                    // 158
    k("HOSolAtTetrahedraP4", true, "hr"),                                                        // 159
    k("HOSolAtPyramidsP4", true, "hr"),                                                          // 160
    k("HOSolAtPrismsP4", true, "hr"),                                                            // 161
    k("HOSolAtHexahedraQ4", true, "hr"),                                                         // 162
    k("HOSolAtEdgesP1NodesPositions", true, "rr"),                                               // 163
    k("HOSolAtEdgesP2NodesPositions", true, "rr"),                                               // 164
    k("HOSolAtEdgesP3NodesPositions", true, "rr"),                                               // 165
    k("HOSolAtEdgesP4NodesPositions", true, "rr"),                                               // 166
    k("HOSolAtTrianglesP1NodesPositions", true, "rrr"),                                          // 167
    k("HOSolAtTrianglesP2NodesPositions", true, "rrr"),                                          // 168
    k("HOSolAtTrianglesP3NodesPositions", true, "rrr"),                                          // 169
    k("HOSolAtTrianglesP4NodesPositions", true, "rrr"),                                          // 170
    k("HOSolAtQuadrilateralsQ1NodesPositions", true, "rr"),                                      // 171
    k("HOSolAtQuadrilateralsQ2NodesPositions", true, "rr"),                                      // 172
    k("HOSolAtQuadrilateralsQ3NodesPositions", true, "rr"),                                      // 173
    k("HOSolAtQuadrilateralsQ4NodesPositions", true, "rr"),                                      // 174
    k("HOSolAtTetrahedraP1NodesPositions", true, "rrrr"),                                        // 175
    k("HOSolAtTetrahedraP2NodesPositions", true, "rrrr"),                                        // 176
    k("HOSolAtTetrahedraP3NodesPositions", true, "rrrr"),                                        // 177
    k("HOSolAtTetrahedraP4NodesPositions", true, "rrrr"),                                        // 178
    k("HOSolAtPyramidsP1NodesPositions", true, "rrr"),                                           // 179
    k("HOSolAtPyramidsP2NodesPositions", true, "rrr"),                                           // 180
    k("HOSolAtPyramidsP3NodesPositions", true, "rrr"),                                           // 181
    k("HOSolAtPyramidsP4NodesPositions", true, "rrr"),                                           // 182
    k("HOSolAtPrismsP1NodesPositions", true, "rrrr"),                                            // 183
    k("HOSolAtPrismsP2NodesPositions", true, "rrrr"),                                            // 184
    k("HOSolAtPrismsP3NodesPositions", true, "rrrr"),                                            // 185
    k("HOSolAtPrismsP4NodesPositions", true, "rrrr"),                                            // 186
    k("HOSolAtHexahedraQ1NodesPositions", true, "rrr"),                                          // 187
    k("HOSolAtHexahedraQ2NodesPositions", true, "rrr"),                                          // 188
    k("HOSolAtHexahedraQ3NodesPositions", true, "rrr"),                                          // 189
    k("HOSolAtHexahedraQ4NodesPositions", true, "rrr"),                                          // 190
    k("EdgesReferenceElement", false, "rr"),                                                     // 191
    k("TriangleReferenceElement", false, "rrrrrr"),                                              // 192
    k("QuadrilateralReferenceElement", false, "rrrrrrrr"),                                       // 193
    k("TetrahedronReferenceElement", false, "rrrrrrrrrrrr"),                                     // 194
    k("PyramidReferenceElement", false, "rrrrrrrrrrrrrrr"),                                      // 195
    k("PrismReferenceElement", false, "rrrrrrrrrrrrrrrrrr"),                                     // 196
    k("HexahedronReferenceElement", false, "rrrrrrrrrrrrrrrrrrrrrrrr"),                          // 197
    k("BoundaryLayers", true, "iii"),                                                            // 198
    k("ReferenceStrings", true, "iic"),                                                          // 199
    k("Prisms9", true, "iiiiiiiiii"),                                                            // 200
    k("Hexahedra12", true, "iiiiiiiiiiiii"),                                                     // 201
    k("Quadrilaterals6", true, "iiiiiii"),                                                       // 202
    k("BoundaryPolygonHeaders", true, "ii"),                                                     // 203
    k("BoundaryPolygonVertices", true, "i"),                                                     // 204
    k("InnerPolygonHeaders", true, "ii"),                                                        // 205
    k("InnerPolygonVertices", true, "i"),                                                        // 206
    k("PolyhedraHeaders", true, "ii"),                                                           // 207
    k("PolyhedraFaces", true, "i"),                                                              // 208
    k("Domains", false, "ii"),                                                                   // 209
    k("VerticesGID", true, "iii"),                                                               // 210
    k("EdgesGID", true, "iii"),                                                                  // 211
    k("TrianglesGID", true, "iii"),                                                              // 212
    k("QuadrilateralsGID", true, "iii"),                                                         // 213
    k("TetrahedraGID", true, "iii"),                                                             // 214
    k("PyramidsGID", true, "iii"),                                                               // 215
    k("PrismsGID", true, "iii"),                                                                 // 216
    k("HexahedraGID", true, "iii"),                                                              // 217
    k("SolAtBoundaryPolygons", true, "sr"),                                                      // 218
    k("SolAtPolyhedra", true, "sr"),                                                             // 219
    k("VertexOnGeometryNode", true, "iiiiii"),                                                   // 220
    k("VertexOnGeometryEdge", true, "iiiiirdrii"),                                               // 221
    k("EdgeOnGeometryEdge", true, "iiiiiii"),                                                    // 222
    k("VertexOnGeometryFace", true, "iiiiirrdrii"),                                              // 223
    k("EdgeOnGeometryFace", true, "iiiiiii"),                                                    // 224
    k("TriangleOnGeometryFace", true, "iiiiiii"),                                                // 225
    k("QuadrialteralOnGeometryFace", true, "iiiiiii"),                                           // 226
    k("MeshOnGeometry", true, "iiiiiidrdrii"),                                                   // 227
    k("VerticesColour", true, "i"),                                                              // 228
    k("VerticesGrain", true, "i"),                                                               // 229
    k("VertexGrainPartitions", true, "ii"),                                                      // 230
    k("EdgeGrainPartitions", true, "ii"),                                                        // 231
    k("TriangleGrainPartitions", true, "ii"),                                                    // 232
    k("QuadrilateralGrainPartitions", true, "ii"),                                               // 233
    k("TetrahedronGrainPartitions", true, "ii"),                                                 // 234
    k("PyramidGrainPartitions", true, "ii"),                                                     // 235
    k("PrismGrainPartitions", true, "ii"),                                                       // 236
    k("HexahedronGrainPartitions", true, "ii"),                                                  // 237
    k("ColorPartitions", true, "ii"),                                                            // 238
    k("TetrahedraColour", true, "i"),                                                            // 239
    k("TetrahedraGrain", true, "i"),                                                             // 240
];
