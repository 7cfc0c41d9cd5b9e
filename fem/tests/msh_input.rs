//! Bad MSH 4.1 input refused before any work, naming the section, the node or element and the line
//! (or byte), and quoting at most one line: node tags honoured whatever the `$Nodes` header says,
//! node and element tags checked against their header, header counts checked against the body
//! (ASCII and binary), causes named right, files read through the mesh size cap.

use fem::gmsh::UnstructuredMesh;
use std::path::PathBuf;

fn path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../meshes")
        .join(name)
}

fn text(name: &str) -> String {
    std::fs::read_to_string(path(name)).unwrap()
}

/// The reader's error on `text`, which must be refused.
fn refused(text: &str) -> String {
    refused_bytes(text.as_bytes())
}

/// Line (1-based) of `text` equal to `line`, from line `from` on.
fn line_no(text: &str, line: &str, from: usize) -> usize {
    1 + from
        + text
            .lines()
            .skip(from)
            .position(|l| l.trim_end() == line)
            .unwrap_or_else(|| panic!("no line {line:?}"))
}

/// `text` with its 1-based line `n` replaced by `by`.
fn with_line(text: &str, n: usize, by: &str) -> String {
    let mut lines: Vec<&str> = text.lines().collect();
    lines[n - 1] = by;
    lines.join("\n") + "\n"
}

/// The first `$Nodes` block of at least two nodes in `text`: (line of its header, node count).
fn block_of_two(text: &str) -> (usize, usize) {
    let lines: Vec<&str> = text.lines().collect();
    let mut i = line_no(text, "$Nodes", 0) + 2;
    loop {
        let f: Vec<usize> = lines[i - 1]
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        if f[3] >= 2 {
            return (i, f[3]);
        }
        i += 1 + 2 * f[3];
    }
}

#[test]
fn two_swapped_nodes_give_the_mesh_the_file_describes() {
    // The first two nodes of a block listed in the other order, tags and coordinates both: the
    // same mesh, though the header still says the tags are consecutive.
    let t = text("rect_tri.msh");
    let (header, n) = block_of_two(&t);
    let lines: Vec<&str> = t.lines().collect();
    let (tag0, tag1) = (lines[header], lines[header + 1]);
    let (x0, x1) = (lines[header + n], lines[header + n + 1]);
    let swapped = with_line(&with_line(&t, header + 1, tag1), header + 2, tag0);
    let swapped = with_line(&with_line(&swapped, header + n + 1, x1), header + n + 2, x0);
    assert_ne!(swapped, t);
    let original = UnstructuredMesh::from_msh_bytes(t.as_bytes()).unwrap();
    let read = UnstructuredMesh::from_msh_bytes(swapped.as_bytes()).unwrap();
    assert_eq!(read.node_tags, original.node_tags);
    assert_eq!(read.positions, original.positions);
    assert_eq!(read.elements, original.elements);
}

#[test]
fn a_duplicated_node_tag_is_refused_with_its_line() {
    let t = text("rect_tri.msh");
    let (header, _) = block_of_two(&t);
    let lines: Vec<&str> = t.lines().collect();
    let first = lines[header];
    let bad = with_line(&t, header + 2, first);
    let e = refused(&bad);
    let want = format!(
        "node tag {first} at line {} is defined twice (first at line {})",
        header + 2,
        header + 1
    );
    assert!(e.contains(&want), "{e}");
}

#[test]
fn node_tags_zero_and_beyond_the_header_are_refused_with_their_lines() {
    let t = text("rect_tri.msh");
    let (header, _) = block_of_two(&t);
    for tag in ["0", "184"] {
        let e = refused(&with_line(&t, header + 1, tag));
        let want = format!(
            "node tag {tag} at line {} is outside the range 1..=183",
            header + 1
        );
        assert!(e.contains(&want), "{tag}: {e}");
    }
}

#[test]
fn a_duplicated_node_tag_in_a_binary_file_is_refused_with_its_offset() {
    let (mut b, _, blocks) = binary_blocks("Nodes");
    let first = blocks.iter().find(|k| k.2 >= 2).unwrap().0 + 20;
    let tag = b[first..first + 8].to_vec();
    b[first + 8..first + 16].copy_from_slice(&tag);
    let e = refused_bytes(&b);
    let tag = u64::from_le_bytes(tag.try_into().unwrap());
    let want = format!("node tag {tag} at byte {} is defined twice", first + 8);
    assert!(e.contains(&want), "{e}");
}

/// `text` with the count line after `$section` (1-based line `n`) replaced by `by`.
fn with_header(text: &str, section: &str, by: &str) -> (String, usize) {
    let n = line_no(text, section, 0) + 1;
    (with_line(text, n, by), n)
}

#[test]
fn header_counts_against_the_body_are_refused_with_both_counts() {
    let t = text("rect_tri.msh");
    let cases = [
        (
            "$Nodes",
            "19 182 1 183",
            "$Nodes header at line {} declares 182 nodes, found 183",
        ),
        (
            "$Nodes",
            "20 183 1 183",
            "$Nodes header at line {} declares 20 entity blocks, found 19",
        ),
        (
            "$PhysicalNames",
            "8",
            "$PhysicalNames header at line {} declares 8 names, found 7",
        ),
        (
            "$Entities",
            "8 9 2 1",
            "$Entities header at line {} declares 20 entities, found 19",
        ),
    ];
    for (section, by, want) in cases {
        let (bad, n) = with_header(&t, section, by);
        let e = refused(&bad);
        assert!(e.contains(&want.replace("{}", &n.to_string())), "{section}: {e}");
    }
    let elements = line_no(&t, "$Elements", 0) + 1;
    let header: Vec<u64> = t
        .lines()
        .nth(elements - 1)
        .unwrap()
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    let bad = with_line(
        &t,
        elements,
        &format!("{} {} {} {}", header[0], header[1] + 1, header[2], header[3]),
    );
    let e = refused(&bad);
    let want = format!(
        "$Elements header at line {elements} declares {} elements, found {}",
        header[1] + 1,
        header[1]
    );
    assert!(e.contains(&want), "{e}");
}

#[test]
fn a_block_count_against_its_lines_is_refused_with_both_counts() {
    let t = text("rect_tri.msh");
    let (header, n) = block_of_two(&t);
    let f: Vec<&str> = t.lines().nth(header - 1).unwrap().split_whitespace().collect();
    let bad = with_line(&t, header, &format!("{} {} {} {}", f[0], f[1], f[2], n + 1));
    let e = refused(&bad);
    let want = format!(
        "$Nodes block header at line {header} declares {} nodes, found {n}",
        n + 1
    );
    assert!(e.contains(&want), "{e}");
}

#[test]
fn an_element_block_count_below_its_lines_is_refused_with_both_counts() {
    let t = text("rect_tri.msh");
    let block = line_no(&t, "$Elements", 0) + 2;
    let f: Vec<&str> = t.lines().nth(block - 1).unwrap().split_whitespace().collect();
    let n: u64 = f[3].parse().unwrap();
    let bad = with_line(&t, block, &format!("{} {} {} {}", f[0], f[1], f[2], n - 1));
    let e = refused(&bad);
    let want = format!(
        "$Elements block header at line {block} declares {} elements, found {n}",
        n - 1
    );
    assert!(e.contains(&want), "{e}");
}

#[test]
fn a_bad_count_in_a_large_mesh_quotes_no_more_than_a_line() {
    let t = text("center-crack-tri.msh");
    assert!(t.len() > 1 << 20);
    let elements = line_no(&t, "$Elements", 0) + 1;
    let first_block = elements + 1;
    let f: Vec<&str> = t
        .lines()
        .nth(first_block - 1)
        .unwrap()
        .split_whitespace()
        .collect();
    let count: u64 = f[3].parse().unwrap();
    let bad = with_line(
        &t,
        first_block,
        &format!("{} {} {} {}", f[0], f[1], f[2], count + 7),
    );
    let e = refused(&bad);
    assert!(e.len() < 400, "{} bytes: {}", e.len(), &e[..400.min(e.len())]);
    assert!(e.contains("$Elements"), "{e}");
}

#[test]
fn a_mesh_without_elements_is_refused_for_that() {
    let t = text("rect_tri.msh");
    let start = line_no(&t, "$Elements", 0);
    let end = line_no(&t, "$EndElements", 0);
    let lines: Vec<&str> = t.lines().collect();
    let mut bad: Vec<&str> = lines[..start].to_vec();
    bad.push("0 0 0 0");
    bad.extend(&lines[end - 1..]);
    let e = refused(&(bad.join("\n") + "\n"));
    assert!(
        e.contains("declares 0 elements") && e.contains(&format!("line {}", start + 1)),
        "{e}"
    );
}

#[test]
fn a_missing_end_of_physical_names_is_named() {
    let t = text("rect_tri.msh").replace("$EndPhysicalNames\n", "");
    let e = refused(&t);
    assert!(
        e.contains("$PhysicalNames opened on line 4 has no $EndPhysicalNames"),
        "{e}"
    );
}

#[test]
fn a_nan_coordinate_names_its_node_and_line() {
    let t = text("rect_tri.msh");
    let (header, n) = block_of_two(&t);
    let tag = t.lines().nth(header).unwrap().trim().to_string();
    let bad = with_line(&t, header + n + 1, "NaN 0 0");
    let e = refused(&bad);
    let want = format!(
        "node {tag} (line {}) has a coordinate that is not a finite number",
        header + n + 1
    );
    assert!(e.contains(&want), "{e}");
}

#[test]
fn dev_zero_as_a_mesh_is_refused_by_the_cap() {
    // The cap is the default 2 GiB: /dev/zero has no size, so the reader stops one byte past it.
    let e = UnstructuredMesh::read(std::path::Path::new("/dev/zero"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("/dev/zero")
            && e.contains("above the cap of 2147483648 bytes")
            && e.contains("COHESIVE_MAX_MESH_BYTES"),
        "{e}"
    );
}

/// The reader's error on the bytes `b`, which must be refused.
fn refused_bytes(b: &[u8]) -> String {
    match UnstructuredMesh::from_msh_bytes(b) {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

/// The binary mixed mesh, the byte offset of the header of its section `$name` (`Nodes` or
/// `Elements`) and its blocks, each as (byte offset of its header, bytes per node or element,
/// count).
fn binary_blocks(name: &str) -> (Vec<u8>, usize, Vec<(usize, usize, u64)>) {
    let b = std::fs::read(path("rect_mixed_bin.msh")).unwrap();
    let body = b
        .windows(name.len() + 2)
        .position(|w| w == format!("${name}\n").as_bytes());
    let body = body.unwrap() + name.len() + 2;
    let word = |at: usize| u64::from_le_bytes(b[at..at + 8].try_into().unwrap());
    let int = |at: usize| i32::from_le_bytes(b[at..at + 4].try_into().unwrap()) as usize;
    // Header: 4 size_t; each block: 3 int + 1 size_t, then its records.
    let (mut blocks, mut at) = (Vec::new(), body + 32);
    for _ in 0..word(body) {
        let record = match name {
            "Nodes" => 8 * (4 + int(at) * int(at + 8)),
            _ => 8 * (1 + [0, 2, 3, 4][int(at + 8)]),
        };
        let n = word(at + 12);
        blocks.push((at, record, n));
        at += 20 + n as usize * record;
    }
    assert_eq!(&b[at..at + 5 + name.len()], format!("\n$End{name}").as_bytes());
    (b, body, blocks)
}

/// `b` with the 8 bytes at `at` set to `value` (little-endian).
fn with_word(b: &[u8], at: usize, value: u64) -> Vec<u8> {
    let mut b = b.to_vec();
    b[at..at + 8].copy_from_slice(&value.to_le_bytes());
    b
}

#[test]
fn binary_counts_against_the_body_are_refused_with_both_counts() {
    for (name, what) in [("Elements", "elements"), ("Nodes", "nodes")] {
        let (b, body, blocks) = binary_blocks(name);
        let total: u64 = blocks.iter().map(|k| k.2).sum();
        let e = refused_bytes(&with_word(&b, body + 8, total + 1));
        let want = format!(
            "${name} header at byte {body} declares {} {what}, found {total}",
            total + 1
        );
        assert!(e.contains(&want), "{e}");
        for by in [n_plus(1), n_plus(-1)] {
            let e = refused_bytes(&with_word(&b, body, by(blocks.len() as u64)));
            let want = format!(
                "${name} header at byte {body} declares {} entity blocks, found {}",
                by(blocks.len() as u64),
                blocks.len()
            );
            assert!(e.contains(&want), "{e}");
        }
        // A block's count one above (the last block) and one below (the first) its records.
        for ((at, _, n), by) in [(blocks[blocks.len() - 1], n_plus(1)), (blocks[0], n_plus(-1))] {
            let e = refused_bytes(&with_word(&b, at + 12, by(n)));
            let want = format!(
                "${name} block header at byte {at} declares {} {what}, found {n}",
                by(n)
            );
            assert!(e.contains(&want), "{e}");
        }
    }
}

/// Adds `d` to a count.
fn n_plus(d: i64) -> impl Fn(u64) -> u64 {
    move |n| n.checked_add_signed(d).unwrap()
}

#[test]
fn element_tags_zero_beyond_the_header_and_twice_are_refused_with_their_lines() {
    let t = text("rect_tri.msh");
    let first = line_no(&t, "$Elements", 0) + 3;
    let second: Vec<&str> = t.lines().nth(first).unwrap().split_whitespace().collect();
    for tag in ["0", "389"] {
        let e = refused(&with_line(&t, first, &format!("{tag} 1 9")));
        let want = format!("element tag {tag} at line {first} is outside the range 1..=388");
        assert!(e.contains(&want), "{tag}: {e}");
    }
    let e = refused(&with_line(&t, first + 1, &format!("1 {}", second[1..].join(" "))));
    let want = format!(
        "element tag 1 at line {} is defined twice (first at line {first})",
        first + 1
    );
    assert!(e.contains(&want), "{e}");
}

#[test]
fn element_tags_in_a_binary_file_zero_beyond_and_twice_are_refused_with_their_offsets() {
    let (b, body, blocks) = binary_blocks("Elements");
    let max = u64::from_le_bytes(b[body + 24..body + 32].try_into().unwrap());
    let (first, record) = (blocks[0].0 + 20, blocks[0].1);
    for tag in [0, max + 1] {
        let e = refused_bytes(&with_word(&b, first, tag));
        let want = format!("element tag {tag} at byte {first} is outside the range 1..={max}");
        assert!(e.contains(&want), "{tag}: {e}");
    }
    let e = refused_bytes(&with_word(&b, first + record, 1));
    let want = format!(
        "element tag 1 at byte {} is defined twice (first at byte {first})",
        first + record
    );
    assert!(e.contains(&want), "{e}");
}

#[test]
fn an_element_on_a_node_the_file_does_not_define_is_refused_naming_both() {
    let t = text("rect_tri.msh");
    let first = line_no(&t, "$Elements", 0) + 3;
    // 0, beyond the header's range, and inside a range widened past the last tag.
    let (wide, _) = with_header(&t, "$Nodes", "19 183 1 200");
    for (file, node) in [(&t, 0), (&t, 184), (&wide, 190)] {
        let e = refused(&with_line(file, first, &format!("1 1 {node}")));
        let want = format!("element 1 references node {node}, which the file does not define");
        assert!(e.contains(&want), "{node}: {e}");
    }
    let (b, _, blocks) = binary_blocks("Elements");
    for node in [0, 184] {
        let e = refused_bytes(&with_word(&b, blocks[0].0 + 28, node));
        let want = format!("element 1 references node {node}, which the file does not define");
        assert!(e.contains(&want), "{node}: {e}");
    }
}
