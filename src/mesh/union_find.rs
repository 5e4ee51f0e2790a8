//! Union–find over `u32` ids whose root is always the smallest member of its set (no paper):
//! shared by the adjacency's components and the segmentation's regions, which number sets in
//! order of their smallest member.
//! Input:  a parent array (`parent[i] = i` to start). Output: roots.
//! Cost:   near-linear (path halving; union by smaller id keeps every step going down).

/// The root of `x`, halving the path on the way. Ends: a parent is never larger than its
/// child, so each step goes to a smaller id.
pub fn find_root(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let up = parent[parent[x as usize] as usize];
        parent[x as usize] = up;
        x = up;
    }
    x
}

/// Joins the sets of `a` and `b`; the smaller root becomes the root.
pub fn union_smallest(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find_root(parent, a), find_root(parent, b));
    let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
    parent[hi as usize] = lo;
}

/// Points every id straight at its root.
pub fn flatten(parent: &mut [u32]) {
    for i in 0..parent.len() {
        parent[i] = find_root(parent, i as u32);
    }
}
