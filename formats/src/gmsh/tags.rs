//! Tag tables: node and element tags to positions ([`TagMap`]), and the element tags of
//! a block as read ([`TagList`]), both without a table while the tags count up by one as
//! Gmsh writes them.

use crate::NodeIndex;

const NONE: usize = usize::MAX;

/// Tag → index: nothing stored when the tags are `first, first + 1, ...` for values
/// `0, 1, ...` (how Gmsh numbers), a dense table when they are nearly contiguous, a
/// sorted one otherwise.
pub(super) enum TagMap {
    Range { first: u64, len: usize },
    Dense(Vec<usize>),
    Sparse(Vec<(u64, usize)>),
}

impl TagMap {
    /// The map of `(tag, value)` pairs; `Err(tag)` names a tag given twice.
    pub(super) fn build<I: Iterator<Item = (u64, usize)> + Clone>(
        items: I,
    ) -> std::result::Result<TagMap, u64> {
        let mut first = None;
        let (count, max, range) = items.clone().fold((0usize, 0u64, true), |(c, m, r), (t, v)| {
            let f = *first.get_or_insert(t);
            (c + 1, m.max(t), r && v == c && t.checked_sub(f) == Some(c as u64))
        });
        if range {
            return Ok(TagMap::Range { first: first.unwrap_or(1), len: count });
        }
        // Dense within a small multiple of the count: memory bounded by the file size.
        if max < (count as u64).saturating_mul(4).saturating_add(1024) {
            let mut table = vec![NONE; max as usize + 1];
            for (t, v) in items {
                let slot = &mut table[t as usize];
                if *slot != NONE {
                    return Err(t);
                }
                *slot = v;
            }
            Ok(TagMap::Dense(table))
        } else {
            let mut v: Vec<(u64, usize)> = items.collect();
            v.sort_unstable();
            if let Some(w) = v.windows(2).find(|w| w[0].0 == w[1].0) {
                return Err(w[0].0);
            }
            Ok(TagMap::Sparse(v))
        }
    }

    /// The position of node `tag` in a map of node positions, which
    /// [`super::reader::Reader::take_node_map`] keeps below `MAX_POINTS`.
    #[inline]
    pub fn node(&self, tag: u64) -> Option<NodeIndex> {
        self.get(tag).map(|v| v as NodeIndex)
    }

    #[inline]
    pub fn get(&self, tag: u64) -> Option<usize> {
        match self {
            TagMap::Range { first, len } => {
                tag.checked_sub(*first).filter(|&d| d < *len as u64).map(|d| d as usize)
            }
            TagMap::Dense(t) => t.get(usize::try_from(tag).ok()?).copied().filter(|&v| v != NONE),
            TagMap::Sparse(v) => v.binary_search_by_key(&tag, |&(t, _)| t).ok().map(|i| v[i].1),
        }
    }
}

/// Element tags of a block: a range while they count up by one, as Gmsh writes them.
pub(super) enum TagList {
    Range { first: u64, len: usize },
    List(Vec<u64>),
}

impl TagList {
    pub fn new() -> Self {
        TagList::Range { first: 0, len: 0 }
    }

    #[inline(always)]
    pub fn push(&mut self, t: u64) {
        // The next tag of a range (the common case) here, anything else out of line.
        if let TagList::Range { first, len } = self {
            if *len > 0 && first.checked_add(*len as u64) == Some(t) {
                *len += 1;
                return;
            }
        }
        self.push_other(t);
    }

    #[inline(never)]
    pub(super) fn push_other(&mut self, t: u64) {
        match self {
            TagList::Range { first, len } => {
                if *len == 0 {
                    *first = t;
                    *len = 1;
                } else if first.checked_add(*len as u64) == Some(t) {
                    *len += 1;
                } else {
                    let mut v: Vec<u64> = (0..*len as u64).map(|i| *first + i).collect();
                    v.push(t);
                    *self = TagList::List(v);
                }
            }
            TagList::List(v) => v.push(t),
        }
    }

    pub fn len(&self) -> usize {
        match self {
            TagList::Range { len, .. } => *len,
            TagList::List(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Room for `n` more tags once they are a list (a range needs none).
    pub fn reserve(&mut self, n: usize) {
        if let TagList::List(v) = self {
            v.reserve(n);
        }
    }

    /// Whether every tag is above the one before it.
    pub(super) fn strictly_ascending(&self) -> bool {
        match self {
            TagList::Range { .. } => true,
            TagList::List(v) => v.windows(2).all(|w| w[0] < w[1]),
        }
    }

    #[inline]
    pub(super) fn get(&self, i: usize) -> u64 {
        match self {
            TagList::Range { first, .. } => first + i as u64,
            TagList::List(v) => v[i],
        }
    }

    pub(super) fn iter(
        &self,
    ) -> impl DoubleEndedIterator<Item = u64> + ExactSizeIterator + Clone + '_ {
        (0..self.len()).map(move |i| self.get(i))
    }

    pub(super) fn contains(&self, t: u64) -> bool {
        match self {
            TagList::Range { first, len } => t.checked_sub(*first).is_some_and(|d| d < *len as u64),
            TagList::List(v) => v.contains(&t),
        }
    }

    /// The last tag if every tag is above `prev` and above the one before it.
    pub(super) fn ascending_after(&self, prev: u64) -> Option<u64> {
        match self {
            TagList::Range { len: 0, .. } => Some(prev),
            TagList::Range { first, len } => (*first > prev).then(|| first + *len as u64 - 1),
            TagList::List(v) => {
                let mut p = prev;
                for &t in v {
                    if t <= p {
                        return None;
                    }
                    p = t;
                }
                Some(p)
            }
        }
    }
}
