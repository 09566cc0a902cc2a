//! The in-memory mesh every format reads into and writes from.
//!
//! A [`TaggedMesh`] is deliberately close to what the files hold: points, blocks of
//! cells of one kind each, one physical and one geometrical (elementary) tag per cell,
//! the names of tags, and named point and cell data. It knows nothing of topology or
//! sizing: those live in the `smartmesh` crate, which builds them *from* the tags.
//!
//! Conventions shared by every reader and writer:
//! - point indices are 0-based into `points`, whatever the file's own numbering;
//! - a tag of `0` means "no tag" (Gmsh 2.2's convention for an element without a
//!   physical group, Triangle's for an unmarked segment);
//! - tensors travel as 9 components, a row-major 3x3 matrix (Gmsh's and ParaView's
//!   layout); a 2D symmetric tensor `[[a, b], [b, c]]` is `[a, b, 0, b, c, 0, 0, 0, zz]`.

use std::collections::BTreeMap;

/// The kind of a cell. First-order cells are what smartmesh computes with; second-order
/// cells are read and kept so that a conversion loses nothing, and a writer whose format
/// cannot hold them says so in its [`crate::WriteReport`].
///
/// Nodes are numbered as Gmsh numbers them (its "node ordering" reference): corners
/// first, then mid-edge nodes in Gmsh's edge order, then mid-face nodes, then the
/// centre. Each other format's reader and writer converts its own order to and from
/// this one (VTK and Medit differ for several second-order volume kinds), so that a cell
/// means the same element whatever the file it came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CellKind {
    /// A single point (Gmsh element type 15, Medit `Corners` are *not* cells).
    Vertex,
    /// A 2-node segment.
    Line,
    /// A 3-node triangle.
    Triangle,
    /// A 4-node quadrilateral.
    Quad,
    /// A 3-node second-order segment (end, end, middle).
    Line3,
    /// A 6-node second-order triangle (corners, then edge middles).
    Triangle6,
    /// An 8-node serendipity quadrilateral.
    Quad8,
    /// A 9-node second-order quadrilateral.
    Quad9,
    /// A 4-node tetrahedron.
    Tetra,
    /// An 8-node hexahedron.
    Hexa,
    /// A 6-node wedge (triangular prism): bottom triangle 0-1-2, top 3-4-5.
    Wedge,
    /// A 5-node pyramid: quadrilateral base 0-1-2-3, apex 4.
    Pyramid,
    /// A 10-node second-order tetrahedron.
    Tetra10,
    /// A 20-node serendipity hexahedron.
    Hexa20,
    /// A 27-node second-order hexahedron.
    Hexa27,
    /// A 15-node serendipity wedge.
    Wedge15,
    /// An 18-node second-order wedge (with the three quadrilateral faces' centres).
    Wedge18,
    /// A 13-node serendipity pyramid.
    Pyramid13,
    /// A 14-node second-order pyramid (with the base's centre).
    Pyramid14,
}

impl CellKind {
    /// Every kind, in a fixed order (the order blocks are sorted in by `TaggedMesh::sort_blocks`).
    pub const ALL: [CellKind; 19] = [
        CellKind::Vertex,
        CellKind::Line,
        CellKind::Triangle,
        CellKind::Quad,
        CellKind::Line3,
        CellKind::Triangle6,
        CellKind::Quad8,
        CellKind::Quad9,
        CellKind::Tetra,
        CellKind::Hexa,
        CellKind::Wedge,
        CellKind::Pyramid,
        CellKind::Tetra10,
        CellKind::Hexa20,
        CellKind::Hexa27,
        CellKind::Wedge15,
        CellKind::Wedge18,
        CellKind::Pyramid13,
        CellKind::Pyramid14,
    ];

    /// Number of nodes of one cell.
    pub const fn nodes_per_cell(self) -> usize {
        match self {
            CellKind::Vertex => 1,
            CellKind::Line => 2,
            CellKind::Triangle => 3,
            CellKind::Quad => 4,
            CellKind::Line3 => 3,
            CellKind::Triangle6 => 6,
            CellKind::Quad8 => 8,
            CellKind::Quad9 => 9,
            CellKind::Tetra => 4,
            CellKind::Hexa => 8,
            CellKind::Wedge => 6,
            CellKind::Pyramid => 5,
            CellKind::Tetra10 => 10,
            CellKind::Hexa20 => 20,
            CellKind::Hexa27 => 27,
            CellKind::Wedge15 => 15,
            CellKind::Wedge18 => 18,
            CellKind::Pyramid13 => 13,
            CellKind::Pyramid14 => 14,
        }
    }

    /// Topological dimension: 0 for vertices, 1 for lines, 2 for surface cells, 3 for
    /// volume cells.
    pub const fn dim(self) -> u8 {
        match self {
            CellKind::Vertex => 0,
            CellKind::Line | CellKind::Line3 => 1,
            CellKind::Triangle
            | CellKind::Quad
            | CellKind::Triangle6
            | CellKind::Quad8
            | CellKind::Quad9 => 2,
            CellKind::Tetra
            | CellKind::Hexa
            | CellKind::Wedge
            | CellKind::Pyramid
            | CellKind::Tetra10
            | CellKind::Hexa20
            | CellKind::Hexa27
            | CellKind::Wedge15
            | CellKind::Wedge18
            | CellKind::Pyramid13
            | CellKind::Pyramid14 => 3,
        }
    }

    /// Whether the cell is second order (has mid-edge or mid-face nodes).
    pub const fn is_second_order(self) -> bool {
        matches!(
            self,
            CellKind::Line3
                | CellKind::Triangle6
                | CellKind::Quad8
                | CellKind::Quad9
                | CellKind::Tetra10
                | CellKind::Hexa20
                | CellKind::Hexa27
                | CellKind::Wedge15
                | CellKind::Wedge18
                | CellKind::Pyramid13
                | CellKind::Pyramid14
        )
    }

    /// The first-order kind of the same shape: the kind itself when first order.
    /// Every second-order kind numbers its corners first, as the linear kind does.
    pub const fn linear(self) -> CellKind {
        match self {
            CellKind::Line3 => CellKind::Line,
            CellKind::Triangle6 => CellKind::Triangle,
            CellKind::Quad8 | CellKind::Quad9 => CellKind::Quad,
            CellKind::Tetra10 => CellKind::Tetra,
            CellKind::Hexa20 | CellKind::Hexa27 => CellKind::Hexa,
            CellKind::Wedge15 | CellKind::Wedge18 => CellKind::Wedge,
            CellKind::Pyramid13 | CellKind::Pyramid14 => CellKind::Pyramid,
            k => k,
        }
    }

    /// The faces of a volume kind by their corners, each ordered so that its right-hand
    /// normal points out of a cell of positive volume (Gmsh's node order); a second-order
    /// kind's faces are its linear kind's, through the corners. Empty for a kind that is
    /// not a volume. The one face table: the boundary skin, the OpenFOAM and Fluent
    /// writers and the volume measures all take it.
    pub const fn faces(self) -> &'static [&'static [usize]] {
        match self.linear() {
            CellKind::Tetra => &[&[0, 2, 1], &[0, 1, 3], &[0, 3, 2], &[1, 2, 3]],
            CellKind::Hexa => &[
                &[0, 3, 2, 1],
                &[4, 5, 6, 7],
                &[0, 1, 5, 4],
                &[1, 2, 6, 5],
                &[2, 3, 7, 6],
                &[3, 0, 4, 7],
            ],
            CellKind::Wedge => {
                &[&[0, 2, 1], &[3, 4, 5], &[0, 1, 4, 3], &[1, 2, 5, 4], &[2, 0, 3, 5]]
            }
            CellKind::Pyramid => &[&[0, 3, 2, 1], &[0, 1, 4], &[1, 2, 4], &[2, 3, 4], &[3, 0, 4]],
            _ => &[],
        }
    }

    /// The Gmsh element type number (MSH 2.2 and 4.1 agree).
    pub const fn gmsh_type(self) -> i32 {
        match self {
            CellKind::Vertex => 15,
            CellKind::Line => 1,
            CellKind::Triangle => 2,
            CellKind::Quad => 3,
            CellKind::Line3 => 8,
            CellKind::Triangle6 => 9,
            CellKind::Quad8 => 16,
            CellKind::Quad9 => 10,
            CellKind::Tetra => 4,
            CellKind::Hexa => 5,
            CellKind::Wedge => 6,
            CellKind::Pyramid => 7,
            CellKind::Tetra10 => 11,
            CellKind::Hexa20 => 17,
            CellKind::Hexa27 => 12,
            CellKind::Wedge15 => 18,
            CellKind::Wedge18 => 13,
            CellKind::Pyramid13 => 19,
            CellKind::Pyramid14 => 14,
        }
    }

    /// The kind of a Gmsh element type number, if smartmesh knows it.
    pub const fn from_gmsh_type(t: i32) -> Option<CellKind> {
        Some(match t {
            15 => CellKind::Vertex,
            1 => CellKind::Line,
            2 => CellKind::Triangle,
            3 => CellKind::Quad,
            8 => CellKind::Line3,
            9 => CellKind::Triangle6,
            16 => CellKind::Quad8,
            10 => CellKind::Quad9,
            4 => CellKind::Tetra,
            5 => CellKind::Hexa,
            6 => CellKind::Wedge,
            7 => CellKind::Pyramid,
            11 => CellKind::Tetra10,
            17 => CellKind::Hexa20,
            12 => CellKind::Hexa27,
            18 => CellKind::Wedge15,
            13 => CellKind::Wedge18,
            19 => CellKind::Pyramid13,
            14 => CellKind::Pyramid14,
            _ => return None,
        })
    }

    /// The VTK cell type number, `None` for a kind VTK has no cell type of (the 14-node
    /// pyramid: VTK's triquadratic pyramid has 19 nodes). The node order of VTK's
    /// second-order volume cells differs from smartmesh's (Gmsh's): the VTK module
    /// converts.
    pub const fn vtk_type(self) -> Option<u8> {
        Some(match self {
            CellKind::Vertex => 1,
            CellKind::Line => 3,
            CellKind::Triangle => 5,
            CellKind::Quad => 9,
            CellKind::Line3 => 21,
            CellKind::Triangle6 => 22,
            CellKind::Quad8 => 23,
            CellKind::Quad9 => 28,
            CellKind::Tetra => 10,
            CellKind::Hexa => 12,
            CellKind::Wedge => 13,
            CellKind::Pyramid => 14,
            CellKind::Tetra10 => 24,
            CellKind::Hexa20 => 25,
            CellKind::Hexa27 => 29,
            CellKind::Wedge15 => 26,
            CellKind::Wedge18 => 32,
            CellKind::Pyramid13 => 27,
            CellKind::Pyramid14 => return None,
        })
    }

    /// The kind of a VTK cell type number, if smartmesh knows it.
    pub const fn from_vtk_type(t: u8) -> Option<CellKind> {
        Some(match t {
            1 => CellKind::Vertex,
            3 => CellKind::Line,
            5 => CellKind::Triangle,
            9 => CellKind::Quad,
            21 => CellKind::Line3,
            22 => CellKind::Triangle6,
            23 => CellKind::Quad8,
            28 => CellKind::Quad9,
            10 => CellKind::Tetra,
            12 => CellKind::Hexa,
            13 => CellKind::Wedge,
            14 => CellKind::Pyramid,
            24 => CellKind::Tetra10,
            25 => CellKind::Hexa20,
            29 => CellKind::Hexa27,
            26 => CellKind::Wedge15,
            32 => CellKind::Wedge18,
            27 => CellKind::Pyramid13,
            _ => return None,
        })
    }

    /// A short lower-case name, as `info` prints it.
    pub const fn name(self) -> &'static str {
        match self {
            CellKind::Vertex => "vertex",
            CellKind::Line => "line",
            CellKind::Triangle => "triangle",
            CellKind::Quad => "quad",
            CellKind::Line3 => "line3",
            CellKind::Triangle6 => "triangle6",
            CellKind::Quad8 => "quad8",
            CellKind::Quad9 => "quad9",
            CellKind::Tetra => "tetra",
            CellKind::Hexa => "hexa",
            CellKind::Wedge => "wedge",
            CellKind::Pyramid => "pyramid",
            CellKind::Tetra10 => "tetra10",
            CellKind::Hexa20 => "hexa20",
            CellKind::Hexa27 => "hexa27",
            CellKind::Wedge15 => "wedge15",
            CellKind::Wedge18 => "wedge18",
            CellKind::Pyramid13 => "pyramid13",
            CellKind::Pyramid14 => "pyramid14",
        }
    }
}

/// A point index in a cell's connectivity (see [`CellBlock`]).
pub type NodeIndex = u32;

/// The largest number of points a mesh's cells can address: indices run below
/// `NodeIndex::MAX`, which readers keep as a value no range check admits.
pub const MAX_POINTS: usize = NodeIndex::MAX as usize;

/// The error a reader reports when `count` of `what` (points, or a point index) pass
/// what 32-bit connectivity can address.
pub(crate) fn past_max_points(what: &str, count: usize) -> crate::ErrorKind {
    crate::ErrorKind::ImplausibleCount {
        what: what.into(),
        count: count as u64,
        limit: format!("{MAX_POINTS} points (32-bit point indices)"),
    }
}

/// `i` as a cell's point index: below [`MAX_POINTS`], else the reader's error.
pub(crate) fn node_index(i: usize) -> Result<NodeIndex, crate::ErrorKind> {
    if i < MAX_POINTS {
        Ok(i as NodeIndex)
    } else {
        Err(past_max_points("point index", i))
    }
}

/// Cells of one kind, stored flat: cell `i` is `nodes[i*k .. (i+1)*k]` with
/// `k = kind.nodes_per_cell()`. `physical[i]` and `geometrical[i]` are its tags.
///
/// Point indices are 32-bit ([`NodeIndex`]): a mesh addresses at most 2^32 - 1 points, the
/// limit of the formats' own 32-bit connectivity (Medit, VTK `int`, Triangle), and the
/// connectivity takes half the memory of `usize` indices. Readers refuse a file whose
/// cells name a point past that limit.
#[derive(Debug, Clone, PartialEq)]
pub struct CellBlock {
    /// The kind of every cell of the block.
    pub kind: CellKind,
    /// Point indices, `kind.nodes_per_cell()` per cell.
    pub nodes: Vec<NodeIndex>,
    /// Physical tag of each cell (Gmsh physical group, Triangle marker or region
    /// attribute, Medit reference, OBJ group); 0 when the file gives none.
    pub physical: Vec<i32>,
    /// Geometrical (elementary) tag of each cell: the Gmsh entity the cell is classified
    /// on. Formats with a single tag store the same value in both.
    pub geometrical: Vec<i32>,
}

impl CellBlock {
    /// Whether the node and tag arrays agree: `nodes_per_cell` nodes and one tag of
    /// each kind per cell.
    pub fn lengths_agree(&self) -> bool {
        self.nodes.len() == self.physical.len() * self.kind.nodes_per_cell()
            && self.geometrical.len() == self.physical.len()
    }

    /// An empty block of `kind`.
    pub fn new(kind: CellKind) -> Self {
        CellBlock { kind, nodes: Vec::new(), physical: Vec::new(), geometrical: Vec::new() }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.physical.len()
    }

    /// Whether the block holds no cell.
    pub fn is_empty(&self) -> bool {
        self.physical.is_empty()
    }

    /// Appends one cell. Its point indices may be given in any integer type (`usize`
    /// from computed indices, `u32` from another block).
    ///
    /// # Panics
    /// If an index is negative or past [`MAX_POINTS`]: the caller's bug, as an index
    /// out of bounds is; readers check what they read before they push it.
    pub fn push<T: Copy + TryInto<NodeIndex>>(
        &mut self,
        nodes: &[T],
        physical: i32,
        geometrical: i32,
    ) {
        debug_assert_eq!(nodes.len(), self.kind.nodes_per_cell());
        self.nodes.extend(nodes.iter().map(|&v| match v.try_into() {
            Ok(v) if (v as usize) < MAX_POINTS => v,
            _ => panic!("a point index past the {MAX_POINTS} points a mesh can address"),
        }));
        self.physical.push(physical);
        self.geometrical.push(geometrical);
    }

    /// How many cells have a geometrical tag other than their physical one: what a
    /// format with one tag per cell loses (it keeps the physical tag).
    pub fn tags_differ(&self) -> usize {
        self.physical.iter().zip(&self.geometrical).filter(|(p, g)| p != g).count()
    }

    /// The nodes of cell `i`.
    pub fn cell(&self, i: usize) -> &[NodeIndex] {
        let k = self.kind.nodes_per_cell();
        &self.nodes[i * k..(i + 1) * k]
    }

    /// Iterator over the cells' node slices.
    pub fn cells(&self) -> std::slice::ChunksExact<'_, NodeIndex> {
        self.nodes.chunks_exact(self.kind.nodes_per_cell())
    }
}

/// A named array of values attached to points or cells, `components` values per item.
///
/// Scalars have 1 component, vectors 3 (2D vectors are stored with z = 0), tensors 9
/// (row-major 3x3) or, packed, 3 (see [`Layout::Symmetric2`]). Other counts are kept as
/// they are.
#[derive(Debug, Clone)]
pub struct DataArray {
    /// Values per point (or cell).
    pub components: usize,
    /// `components * n` values, item-major.
    pub values: Vec<f64>,
    /// How an item's values are laid out.
    pub layout: Layout,
}

/// How the values of one item of a [`DataArray`] are laid out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Layout {
    /// The `components` values as the file gives them.
    #[default]
    Plain,
    /// A symmetric 2D tensor packed as `m11 m12 m22` (3 components), standing for the
    /// row-major 3x3 tensor `[m11 m12 0; m12 m22 0; 0 0 1]`. The Medit reader keeps
    /// 2D solution tensors so: a third of the memory of the full tensor, which a
    /// 1.5-million-triangle read would otherwise spend most of its time faulting in.
    /// Writers of 9-component formats expand it ([`DataArray::expanded`]).
    Symmetric2,
}

impl DataArray {
    /// Whether the array holds exactly `items` items (and whole ones).
    pub fn covers(&self, items: usize) -> bool {
        self.components != 0 && self.values.len() % self.components == 0 && self.len() == items
    }

    /// A new array; `values.len()` must be a multiple of `components`.
    pub fn new(components: usize, values: Vec<f64>) -> Self {
        debug_assert!(components > 0 && values.len() % components == 0);
        DataArray { components, values, layout: Layout::Plain }
    }

    /// A packed array of symmetric 2D tensors, `m11 m12 m22` per item
    /// ([`Layout::Symmetric2`]); `values.len()` must be a multiple of 3.
    pub fn symmetric2(values: Vec<f64>) -> Self {
        debug_assert!(values.len() % 3 == 0);
        DataArray { components: 3, values, layout: Layout::Symmetric2 }
    }

    /// Number of items (points or cells) the array covers.
    pub fn len(&self) -> usize {
        self.values.len().checked_div(self.components).unwrap_or(0)
    }

    /// Whether the array covers no item.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The values of item `i`, as stored (packed for [`Layout::Symmetric2`]).
    pub fn item(&self, i: usize) -> &[f64] {
        &self.values[i * self.components..(i + 1) * self.components]
    }

    /// What the array looks like to a user: scalar, vector, tensor or other.
    pub fn shape(&self) -> DataShape {
        match (self.layout, self.components) {
            (Layout::Symmetric2, _) => DataShape::Tensor,
            (_, 1) => DataShape::Scalar,
            (_, 2 | 3) => DataShape::Vector,
            (_, 9) => DataShape::Tensor,
            _ => DataShape::Other,
        }
    }

    /// Whether the items are tensors (9 components, or packed symmetric 2D ones).
    pub fn is_tensor(&self) -> bool {
        self.shape() == DataShape::Tensor
    }

    /// Item `i` of a tensor array as the row-major 3x3 tensor (see [`Self::is_tensor`]).
    pub fn tensor9(&self, i: usize) -> [f64; 9] {
        let t = self.item(i);
        match self.layout {
            Layout::Symmetric2 => sym2_to_tensor9(t[0], t[1], t[2], 1.0),
            Layout::Plain => std::array::from_fn(|j| t[j]),
        }
    }

    /// Components per item once expanded ([`Self::expanded`]): 9 for a packed
    /// symmetric tensor, else `components`.
    pub fn expanded_components(&self) -> usize {
        match self.layout {
            Layout::Symmetric2 => 9,
            Layout::Plain => self.components,
        }
    }

    /// The array with every item as the file formats that store full values hold it: a
    /// packed [`Layout::Symmetric2`] array becomes 9 components; others are lent as
    /// they are.
    pub fn expanded(&self) -> std::borrow::Cow<'_, DataArray> {
        match self.layout {
            Layout::Plain => std::borrow::Cow::Borrowed(self),
            Layout::Symmetric2 => std::borrow::Cow::Owned(DataArray::new(
                9,
                (0..self.len()).flat_map(|i| self.tensor9(i)).collect(),
            )),
        }
    }
}

/// Arrays are equal when they hold the same values item by item once expanded: a packed
/// symmetric 2D tensor equals the 9-component tensor it stands for.
impl PartialEq for DataArray {
    fn eq(&self, other: &Self) -> bool {
        if self.layout == other.layout {
            return self.components == other.components && self.values == other.values;
        }
        let (a, b) = (self.expanded(), other.expanded());
        a.components == b.components && a.values == b.values
    }
}

/// How a [`DataArray`] is meant to be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DataShape {
    /// One value per item.
    Scalar,
    /// 2 or 3 values per item.
    Vector,
    /// 9 values per item, a row-major 3x3 matrix.
    Tensor,
    /// Any other count.
    Other,
}

/// A point inside a region of a planar straight-line graph (Triangle `.poly`), with the
/// region's attribute and area bound. Used by the mesher; kept through conversions
/// between formats that can hold it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionSeed {
    /// A point strictly inside the region.
    pub point: [f64; 2],
    /// The regional attribute, a real as in Triangle: the face tag of the region's
    /// triangles when every region's attribute is an integer.
    pub attribute: f64,
    /// Maximum triangle area in the region; negative when unconstrained.
    pub max_area: f64,
}

/// A 2D (or 3D, when a file says so) mesh with tags and fields.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TaggedMesh {
    /// Point coordinates. z is 0 for 2D files and kept when a file has it.
    pub points: Vec<[f64; 3]>,
    /// 2 when every coordinate is planar as written (Triangle, Medit `Dimension 2`),
    /// 3 when the file stores three coordinates per point.
    pub coordinate_dim: u8,
    /// Cell blocks, in file order. Several blocks may share a kind.
    pub blocks: Vec<CellBlock>,
    /// Names of physical tags: `(dimension, tag) -> name` (Gmsh `$PhysicalNames`, OBJ
    /// groups, ...).
    pub tag_names: BTreeMap<(u8, i32), String>,
    /// Physical tags of each geometrical entity `(dimension, entity tag)`, as Gmsh 4.1's
    /// `$Entities` lists them. May list several physical groups per entity and entities
    /// without cells (a Gmsh point entity, say). Empty when the file has no such table.
    pub entities: BTreeMap<(u8, i32), Vec<i32>>,
    /// The bounding box `[xmin, ymin, zmin, xmax, ymax, zmax]` of each geometrical entity
    /// `(dimension, entity tag)` as a file gives it (Gmsh 4.1's `$Entities`: the model's
    /// boxes, which may be larger than the nodes'; a point entity's coordinates twice).
    /// The Gmsh writer keeps a box that holds the entity's nodes and computes the others.
    pub entity_boxes: BTreeMap<(u8, i32), [f64; 6]>,
    /// Named point data, one item per point.
    pub point_data: BTreeMap<String, DataArray>,
    /// Named cell data, one item per cell over all blocks in block order.
    pub cell_data: BTreeMap<String, DataArray>,
    /// Named sets of point indices that a format keeps apart from cells (Medit
    /// `Corners`, `RequiredVertices`).
    pub point_sets: BTreeMap<String, Vec<usize>>,
    /// Named sets of cell indices (global, over all blocks in block order), such as
    /// Medit `Ridges` or `RequiredEdges`.
    pub cell_sets: BTreeMap<String, Vec<usize>>,
    /// Hole points of a planar straight-line graph (Triangle `.poly`).
    pub holes: Vec<[f64; 2]>,
    /// Region seeds of a planar straight-line graph (Triangle `.poly`).
    pub regions: Vec<RegionSeed>,
}

impl TaggedMesh {
    /// An empty 2D mesh.
    pub fn new() -> Self {
        TaggedMesh { coordinate_dim: 2, ..Default::default() }
    }

    /// Total number of cells over all blocks.
    pub fn num_cells(&self) -> usize {
        self.blocks.iter().map(CellBlock::len).sum()
    }

    /// Number of cells of `kind` over all blocks.
    pub fn num_cells_of(&self, kind: CellKind) -> usize {
        self.blocks.iter().filter(|b| b.kind == kind).map(CellBlock::len).sum()
    }

    /// The block of `kind` at the end of `blocks`, created if the last block has
    /// another kind. Readers use it to append cells while keeping file order.
    pub fn block_mut(&mut self, kind: CellKind) -> &mut CellBlock {
        if self.blocks.last().map(|b| b.kind) != Some(kind) {
            self.blocks.push(CellBlock::new(kind));
        }
        self.blocks.last_mut().expect("just pushed")
    }

    /// Iterator over `(kind, nodes, physical, geometrical)` of every cell in block order.
    pub fn cells(&self) -> impl Iterator<Item = (CellKind, &[NodeIndex], i32, i32)> + '_ {
        self.blocks.iter().flat_map(|b| {
            b.cells()
                .zip(b.physical.iter().zip(&b.geometrical))
                .map(move |(n, (&p, &g))| (b.kind, n, p, g))
        })
    }

    /// Merges consecutive blocks of the same kind (cell order and cell data unchanged).
    pub fn merge_adjacent_blocks(&mut self) {
        let mut merged: Vec<CellBlock> = Vec::with_capacity(self.blocks.len());
        for b in self.blocks.drain(..) {
            match merged.last_mut() {
                Some(last) if last.kind == b.kind => {
                    last.nodes.extend(b.nodes);
                    last.physical.extend(b.physical);
                    last.geometrical.extend(b.geometrical);
                }
                _ => merged.push(b),
            }
        }
        self.blocks = merged;
    }

    /// Splits every 4-node quad into two triangles, in place: the diagonal whose two
    /// triangles have the better worst shape (the shorter one on a square), each triangle
    /// with the quad's tags and a copy of its cell data; cell sets name both halves.
    /// Returns how many quads were split. For writers of formats without quads and for
    /// callers that need triangles only.
    pub fn split_quads(&mut self) -> usize {
        let quads = self.num_cells_of(CellKind::Quad);
        if quads == 0 {
            return 0;
        }
        let shape = |p: [[f64; 3]; 3]| -> f64 {
            let l2 = |a: [f64; 3], b: [f64; 3]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
            let s = l2(p[0], p[1]) + l2(p[1], p[2]) + l2(p[2], p[0]);
            let area = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
            if s > 0.0 {
                area / s
            } else {
                0.0
            }
        };
        // Old global cell index -> new indices (one or two).
        let mut new_of: Vec<(usize, Option<usize>)> = Vec::with_capacity(self.num_cells());
        let mut next = 0;
        for b in &mut self.blocks {
            if b.kind != CellKind::Quad {
                for _ in 0..b.len() {
                    new_of.push((next, None));
                    next += 1;
                }
                continue;
            }
            let mut t = CellBlock::new(CellKind::Triangle);
            let points = &self.points;
            for (i, c) in b.cells().enumerate() {
                let p = |k: usize| points[c[k] as usize];
                let first = shape([p(0), p(1), p(2)]).min(shape([p(0), p(2), p(3)]));
                let second = shape([p(0), p(1), p(3)]).min(shape([p(1), p(2), p(3)]));
                let (ph, ge) = (b.physical[i], b.geometrical[i]);
                if first >= second {
                    t.push(&[c[0], c[1], c[2]], ph, ge);
                    t.push(&[c[0], c[2], c[3]], ph, ge);
                } else {
                    t.push(&[c[0], c[1], c[3]], ph, ge);
                    t.push(&[c[1], c[2], c[3]], ph, ge);
                }
                new_of.push((next, Some(next + 1)));
                next += 2;
            }
            *b = t;
        }
        for a in self.cell_data.values_mut() {
            if a.len() != new_of.len() {
                continue;
            }
            let k = a.components;
            let mut v = Vec::with_capacity(next * k);
            for (i, &(_, second)) in new_of.iter().enumerate() {
                v.extend_from_slice(&a.values[i * k..(i + 1) * k]);
                if second.is_some() {
                    v.extend_from_slice(&a.values[i * k..(i + 1) * k]);
                }
            }
            a.values = v;
        }
        for set in self.cell_sets.values_mut() {
            let mut out = Vec::with_capacity(set.len());
            for &c in set.iter() {
                if let Some(&(a, b)) = new_of.get(c) {
                    out.push(a);
                    out.extend(b);
                }
            }
            *set = out;
        }
        quads
    }

    /// The name of physical tag `tag` of dimension `dim`, if the file named it.
    pub fn tag_name(&self, dim: u8, tag: i32) -> Option<&str> {
        self.tag_names.get(&(dim, tag)).map(String::as_str)
    }

    /// Axis-aligned bounding box `(min, max)` of the points, `None` when there are none.
    pub fn bounding_box(&self) -> Option<([f64; 3], [f64; 3])> {
        let mut it = self.points.iter();
        let first = *it.next()?;
        let (mut lo, mut hi) = (first, first);
        for p in it {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        Some((lo, hi))
    }

    /// Every problem that makes the mesh unusable or inconsistent, empty when none:
    /// out-of-range indices, non-finite coordinates, data arrays of the wrong length.
    /// Orientation and quality are the `smartmesh` crate's business.
    pub fn validate(&self) -> Vec<MeshProblem> {
        let mut problems = Vec::new();
        let n = self.points.len();
        // Each check is first one branch-free pass (what a large mesh costs); the
        // culprits are looked for only when it fails.
        if !self.points.as_flattened().iter().fold(true, |ok, c| ok & c.is_finite()) {
            for (i, p) in self.points.iter().enumerate() {
                if !p.iter().all(|c| c.is_finite()) {
                    problems.push(MeshProblem::NonFiniteCoordinate { point: i });
                }
            }
        }
        let mut offset = 0;
        for (bi, b) in self.blocks.iter().enumerate() {
            if !b.lengths_agree() {
                problems.push(MeshProblem::BlockLengths { block: bi });
                continue;
            }
            if b.nodes.iter().fold(0, |m, &v| m.max(v)) as usize >= n {
                for (ci, cell) in b.cells().enumerate() {
                    if let Some(&bad) = cell.iter().find(|&&v| v as usize >= n) {
                        problems.push(MeshProblem::NodeOutOfRange {
                            cell: offset + ci,
                            node: bad as usize,
                        });
                    }
                }
            }
            offset += b.len();
        }
        for (name, a) in &self.point_data {
            if !a.covers(n) {
                problems.push(MeshProblem::DataLength {
                    name: name.clone(),
                    expected: n,
                    found: a.len(),
                });
            }
        }
        let nc = self.num_cells();
        for (name, a) in &self.cell_data {
            if !a.covers(nc) {
                problems.push(MeshProblem::DataLength {
                    name: name.clone(),
                    expected: nc,
                    found: a.len(),
                });
            }
        }
        for (name, set) in &self.point_sets {
            if let Some(&bad) = set.iter().find(|&&v| v >= n) {
                problems.push(MeshProblem::SetOutOfRange { name: name.clone(), index: bad });
            }
        }
        for (name, set) in &self.cell_sets {
            if let Some(&bad) = set.iter().find(|&&v| v >= nc) {
                problems.push(MeshProblem::SetOutOfRange { name: name.clone(), index: bad });
            }
        }
        problems
    }

    /// The checks of [`TaggedMesh::validate`] that do not read every point and cell:
    /// whether block, data and set lengths agree and set items are in range. A writer
    /// that checks coordinates and node numbers as it writes them calls this first,
    /// and [`TaggedMesh::validate`] for the message when something fails.
    pub fn lengths_agree(&self) -> bool {
        let (n, nc) = (self.points.len(), self.num_cells());
        self.blocks.iter().all(CellBlock::lengths_agree)
            && self.point_data.values().all(|a| a.covers(n))
            && self.cell_data.values().all(|a| a.covers(nc))
            && self.point_sets.values().all(|s| s.iter().all(|&v| v < n))
            && self.cell_sets.values().all(|s| s.iter().all(|&v| v < nc))
    }
}

/// One problem found by [`TaggedMesh::validate`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshProblem {
    /// A coordinate is NaN or infinite.
    #[error("point {point} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// 0-based point index.
        point: usize,
    },
    /// A cell refers to a point that does not exist.
    #[error("cell {cell} refers to point {node}, which does not exist")]
    NodeOutOfRange {
        /// Global 0-based cell index.
        cell: usize,
        /// The offending point index.
        node: usize,
    },
    /// A block's node and tag arrays disagree in length.
    #[error("block {block} has node and tag arrays of inconsistent lengths")]
    BlockLengths {
        /// Block index.
        block: usize,
    },
    /// A data array does not cover every point (or cell).
    #[error("data array `{name}` has {found} items, expected {expected}")]
    DataLength {
        /// Array name.
        name: String,
        /// Expected item count.
        expected: usize,
        /// Item count found.
        found: usize,
    },
    /// A point or cell set names an index that does not exist.
    #[error("set `{name}` refers to index {index}, which does not exist")]
    SetOutOfRange {
        /// Set name.
        name: String,
        /// The offending index.
        index: usize,
    },
}

/// Converts a 2D symmetric tensor `(m11, m12, m22)` to the 9-component row-major layout,
/// with `zz` on the third diagonal entry.
pub fn sym2_to_tensor9(m11: f64, m12: f64, m22: f64, zz: f64) -> [f64; 9] {
    [m11, m12, 0.0, m12, m22, 0.0, 0.0, 0.0, zz]
}

/// The 2D symmetric part `(m11, m12, m22)` of a 9-component row-major tensor
/// (off-diagonal terms averaged).
pub fn tensor9_to_sym2(t: &[f64]) -> (f64, f64, f64) {
    (t[0], 0.5 * (t[1] + t[3]), t[4])
}
