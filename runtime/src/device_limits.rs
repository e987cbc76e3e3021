//! What one picture needs of the device, checked before any work: a render target is a 2D
//! texture (at most `max_texture_dimension_2d` per side) and the finished frame comes back
//! through one buffer of the widest target format (at most `max_buffer_size` bytes). A size the
//! command line accepts but this device cannot hold is refused here, with the device's limit
//! and the largest picture it does hold, instead of failing inside wgpu after the work.

use crate::error::RuntimeError;
use crate::gpu::Gpu;

/// Bytes per texel of the widest target read back (linear RGBA, f32 each).
const WIDEST_TEXEL_BYTES: u64 = 16;

/// Bytes of one row of `width` texels of `texel_bytes` each, padded as buffer copies require.
fn padded_row_bytes(width: u32, texel_bytes: u32) -> u64 {
    (u64::from(width) * u64::from(texel_bytes)).div_ceil(256) * 256
}

/// Bytes of the readback of a `width`×`height` picture.
fn readback_bytes(width: u32, height: u32) -> u64 {
    padded_row_bytes(width, WIDEST_TEXEL_BYTES as u32) * u64::from(height)
}

/// Bytes for people, exact too: two sizes that round alike must still read apart.
fn bytes(n: u64) -> String {
    const GIB: f64 = (1u64 << 30) as f64;
    const MIB: f64 = (1u64 << 20) as f64;
    if n as f64 >= GIB {
        format!("{:.2} GiB ({n} bytes)", n as f64 / GIB)
    } else {
        format!("{:.1} MiB ({n} bytes)", n as f64 / MIB)
    }
}

impl Gpu {
    /// Checks that a `width`×`height` picture (`what`, e.g. "the image") fits this device's
    /// limits; the error gives the limit and the largest square picture that fits.
    pub fn check_picture(&self, what: &str, width: u32, height: u32) -> Result<(), RuntimeError> {
        let limits = self.device().limits();
        let side = limits.max_texture_dimension_2d;
        let largest = largest_square(side, limits.max_buffer_size);
        let way_out = format!(
            "the largest picture it renders is {side} px on a side, {largest}x{largest} as a \
             square: ask for a smaller one"
        );
        if width == 0 || height == 0 || width > side || height > side {
            return Err(RuntimeError::DeviceLimit {
                what: format!("{what} of {width}x{height}"),
                needs: format!("{} px on a side", width.max(height)),
                allows: format!("{side} px per side of a texture"),
                adapter: self.info().to_string(),
                way_out,
            });
        }
        let needed = readback_bytes(width, height);
        if needed > limits.max_buffer_size {
            return Err(RuntimeError::DeviceLimit {
                what: format!("{what} of {width}x{height}"),
                needs: format!("{} to read back", bytes(needed)),
                allows: format!("{} per buffer", bytes(limits.max_buffer_size)),
                adapter: self.info().to_string(),
                way_out,
            });
        }
        Ok(())
    }
}

/// The largest square side at most `side` whose readback fits `max_buffer` bytes.
fn largest_square(side: u32, max_buffer: u64) -> u32 {
    let (mut lo, mut hi) = (0u32, side);
    while lo < hi {
        let mid = lo + (hi - lo).div_ceil(2);
        if readback_bytes(mid, mid) <= max_buffer {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_square_is_the_last_that_fits() {
        let max = (1u64 << 32) - 1;
        let s = largest_square(16384, max);
        assert!(readback_bytes(s, s) <= max && readback_bytes(s + 1, s + 1) > max);
        assert_eq!(s, 16383.min(s), "{s}");
        assert_eq!(largest_square(100, u64::MAX), 100);
        assert_eq!(padded_row_bytes(1, 16), 256);
        assert_eq!(readback_bytes(16384, 16384), 1 << 32);
    }
}
