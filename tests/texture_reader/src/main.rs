//! Prints a KTX2 or DDS texture as the `ktx2` / `ddsfile` crates read it: a first line
//! `format width height channels depth` (the format by the container's own name for it:
//! the `VkFormat` of a KTX2, the `DXGI_FORMAT` of a DDS; depth 1 for a 2-D texture), then
//! one line per texel row with the decoded values (row-major, channels interleaved,
//! shortest round-trip decimals; a 3-D texture's slices one after another).
//!
//! Usage: `texture_reader <file.ktx2|file.dds>`. Exits with 1 and a message on stderr
//! when the crates refuse the file or its format is not one this reader decodes.

use std::process::ExitCode;

/// How texels are stored: the channel count, bits per channel and encoding.
#[derive(Clone, Copy)]
struct Layout {
    channels: usize,
    bits: usize,
    float: bool,
}

/// The layout of a format from its name (`R16G16_SFLOAT`, `R16G16_Float`, `R16_UNorm`).
fn layout(name: &str) -> Option<Layout> {
    let upper = name.to_ascii_uppercase();
    let (components, encoding) = upper.split_once('_')?;
    let float = match encoding {
        "SFLOAT" | "FLOAT" => true,
        "UNORM" => false,
        _ => return None,
    };
    let mut bits = Vec::new();
    for part in components
        .split(['R', 'G', 'B', 'A'])
        .filter(|p| !p.is_empty())
    {
        bits.push(part.parse::<usize>().ok()?);
    }
    let first = *bits.first()?;
    if bits.iter().any(|&b| b != first) || !matches!(first, 16 | 32) || (!float && first != 16) {
        return None;
    }
    Some(Layout {
        channels: bits.len(),
        bits: first,
        float,
    })
}

fn decode(data: &[u8], layout: Layout) -> Vec<f64> {
    let size = layout.bits / 8;
    data.chunks_exact(size)
        .map(|b| match (layout.bits, layout.float) {
            (16, true) => f64::from(half::f16::from_le_bytes([b[0], b[1]]).to_f32()),
            (16, false) => f64::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0,
            _ => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        })
        .collect()
}

/// A texture as read: its format's name, width, height, depth and texels.
type Texture = (String, usize, usize, usize, Vec<f64>, Layout);

fn read(path: &str) -> Result<Texture, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
    let (name, width, height, depth, data) = if path.ends_with(".ktx2") {
        let reader = ktx2::Reader::new(bytes.as_slice()).map_err(|e| format!("ktx2: {e:?}"))?;
        let header = reader.header();
        if header.supercompression_scheme.is_some() {
            return Err("ktx2: supercompressed".into());
        }
        let format = header.format.ok_or("ktx2: VK_FORMAT_UNDEFINED")?;
        let level = reader.levels().next().ok_or("ktx2: no level")?;
        (
            format!("{format:?}"),
            header.pixel_width as usize,
            header.pixel_height.max(1) as usize,
            header.pixel_depth.max(1) as usize,
            level.data.to_vec(),
        )
    } else if path.ends_with(".dds") {
        let dds = ddsfile::Dds::read(bytes.as_slice()).map_err(|e| format!("dds: {e}"))?;
        let format = dds.get_dxgi_format().ok_or("dds: no DXGI format")?;
        let data = dds.get_data(0).map_err(|e| format!("dds: {e}"))?;
        (
            format!("{format:?}"),
            dds.get_width() as usize,
            dds.get_height() as usize,
            dds.get_depth() as usize,
            data.to_vec(),
        )
    } else {
        return Err(format!("{path}: expected a .ktx2 or .dds file"));
    };
    let layout =
        layout(&name).ok_or_else(|| format!("{name}: a format this reader does not decode"))?;
    let expected = width * height * depth * layout.channels * layout.bits / 8;
    if data.len() < expected {
        return Err(format!(
            "{name}: {} bytes of texels, {expected} expected",
            data.len()
        ));
    }
    let values = decode(&data[..expected], layout);
    Ok((name, width, height, depth, values, layout))
}

fn main() -> ExitCode {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: texture_reader <file.ktx2|file.dds>");
        return ExitCode::FAILURE;
    };
    match read(&path) {
        Ok((name, width, height, depth, values, layout)) => {
            println!("{name} {width} {height} {} {depth}", layout.channels);
            for row in values.chunks(width * layout.channels) {
                let text: Vec<String> = row.iter().map(|v| format!("{v:?}")).collect();
                println!("{}", text.join(" "));
            }
            ExitCode::SUCCESS
        }
        Err(message) => {
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}
