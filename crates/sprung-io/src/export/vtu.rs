//! VTK XML unstructured grid frames (`.vtu`): the [`Frame`] with every
//! array in binary, zlib-compressed, base64-encoded inline, as VTK writes
//! them itself (`header_type="UInt64"`, `vtkZLibDataCompressor`). ParaView,
//! VTK, pyvista and meshio read them; `sprung render` reads them back
//! ([`super::read_vtk_frame`]).
//!
//! Each array's text is the base64 of its block header (the number of
//! blocks, the block size, the size of the last block when it is partial,
//! then each block's compressed size, all `u64`) followed by the base64 of
//! the compressed blocks.

use std::fmt::Write;
use std::io::Write as _;

use base64::engine::general_purpose::STANDARD;
use base64::Engine;
use flate2::write::ZlibEncoder;
use flate2::Compression;
use sprung::World;

use super::frame::Frame;

/// Uncompressed bytes per compressed block (VTK's own default).
pub(crate) const BLOCK_SIZE: usize = 1 << 15;

/// The world's current state as a `.vtu` file.
pub(crate) fn render(world: &World) -> Vec<u8> {
    let frame = Frame::of(world);
    let particles = &world.particles;
    let mut out = String::new();
    // Writing to a String cannot fail; the results are ignored on purpose.
    let _ = writeln!(out, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        out,
        "<!-- sprung frame: step {} time {} s -->",
        world.steps(),
        world.time()
    );
    let _ = writeln!(
        out,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">"
    );
    let _ = writeln!(out, "<UnstructuredGrid>");
    let _ = writeln!(out, "<FieldData>");
    array(
        &mut out,
        "Float64",
        "TIME",
        1,
        &bytes_f64([world.time()].into_iter()),
        Some(1),
    );
    let _ = writeln!(out, "</FieldData>");
    let _ = writeln!(
        out,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        particles.len(),
        frame.cells()
    );
    let vectors = |v: &[sprung::Vec3]| bytes_f64(v.iter().flat_map(|x| x.to_array()));
    let _ = writeln!(out, "<Points>");
    array(
        &mut out,
        "Float64",
        "position",
        3,
        &vectors(&particles.position),
        None,
    );
    let _ = writeln!(out, "</Points>");
    let _ = writeln!(out, "<Cells>");
    let ints = |v: &[u32]| bytes_i32(v.iter().map(|&x| x as i32));
    array(
        &mut out,
        "Int32",
        "connectivity",
        1,
        &ints(&frame.connectivity),
        None,
    );
    array(&mut out, "Int32", "offsets", 1, &ints(&frame.offsets), None);
    array(&mut out, "UInt8", "types", 1, &frame.types, None);
    let _ = writeln!(out, "</Cells>");
    let _ = writeln!(out, "<PointData Vectors=\"velocity\">");
    array(
        &mut out,
        "Float64",
        "velocity",
        3,
        &vectors(&particles.velocity),
        None,
    );
    array(&mut out, "UInt8", "pinned", 1, &frame.pinned, None);
    array(
        &mut out,
        "Int32",
        "body",
        1,
        &bytes_i32(frame.point_body.iter().copied()),
        None,
    );
    let _ = writeln!(out, "</PointData>");
    let _ = writeln!(out, "<CellData Scalars=\"strain\">");
    array(&mut out, "UInt8", "kind", 1, &frame.kind, None);
    array(
        &mut out,
        "Int32",
        "body",
        1,
        &bytes_i32(frame.cell_body.iter().copied()),
        None,
    );
    array(
        &mut out,
        "Float64",
        "rest_length",
        1,
        &bytes_f64(frame.rest_length.iter().copied()),
        None,
    );
    array(
        &mut out,
        "Float64",
        "strain",
        1,
        &bytes_f64(frame.strain.iter().copied()),
        None,
    );
    let _ = writeln!(out, "</CellData>");
    let _ = writeln!(out, "</Piece>\n</UnstructuredGrid>\n</VTKFile>");
    out.into_bytes()
}

fn bytes_f64(values: impl Iterator<Item = f64>) -> Vec<u8> {
    values.flat_map(f64::to_le_bytes).collect()
}

fn bytes_i32(values: impl Iterator<Item = i32>) -> Vec<u8> {
    values.flat_map(i32::to_le_bytes).collect()
}

/// One `DataArray` of `components` per tuple holding `bytes`, compressed;
/// `tuples` is written for field data.
fn array(
    out: &mut String,
    kind: &str,
    name: &str,
    components: usize,
    bytes: &[u8],
    tuples: Option<usize>,
) {
    let tuples = tuples
        .map(|n| format!(" NumberOfTuples=\"{n}\""))
        .unwrap_or_default();
    let _ = writeln!(
        out,
        "<DataArray type=\"{kind}\" Name=\"{name}\" NumberOfComponents=\"{components}\"{tuples} format=\"binary\">"
    );
    let (header, data) = compress(bytes);
    STANDARD.encode_string(header, out);
    STANDARD.encode_string(data, out);
    let _ = writeln!(out, "\n</DataArray>");
}

/// The block header and the compressed blocks of `bytes`.
fn compress(bytes: &[u8]) -> (Vec<u8>, Vec<u8>) {
    let blocks: Vec<Vec<u8>> = bytes
        .chunks(BLOCK_SIZE)
        .map(|block| {
            let mut encoder = ZlibEncoder::new(Vec::new(), Compression::default());
            // Writing into a Vec cannot fail.
            let _ = encoder.write_all(block);
            encoder.finish().unwrap_or_default()
        })
        .collect();
    let last = bytes.len() % BLOCK_SIZE;
    let mut header = vec![blocks.len() as u64, BLOCK_SIZE as u64, last as u64];
    header.extend(blocks.iter().map(|b| b.len() as u64));
    let header = header.iter().flat_map(|h| h.to_le_bytes()).collect();
    (header, blocks.concat())
}
