//! The byte codec of engine checkpoints: little-endian f64 and u64 words, lengths before
//! sequences, usize::MAX (a "none" index) as u64::MAX on every platform. Readers check
//! every length against the bytes left, so malformed input is an error, never a panic.

use crate::error::{Error, Result};

/// Writes checkpoint words into a byte vector.
pub(crate) struct Writer(pub(crate) Vec<u8>);

impl Writer {
    pub(crate) fn f(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub(crate) fn u(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub(crate) fn z(&mut self, x: usize) {
        self.u(if x == usize::MAX { u64::MAX } else { x as u64 });
    }
    pub(crate) fn b(&mut self, x: bool) {
        self.u(u64::from(x));
    }
    pub(crate) fn i(&mut self, x: i8) {
        self.u(x as i64 as u64);
    }
    pub(crate) fn fs(&mut self, v: &[f64]) {
        self.u(v.len() as u64);
        for &x in v {
            self.f(x);
        }
    }
    pub(crate) fn zs(&mut self, v: &[usize]) {
        self.u(v.len() as u64);
        for &x in v {
            self.z(x);
        }
    }
    pub(crate) fn us(&mut self, v: &[u64]) {
        self.u(v.len() as u64);
        for &x in v {
            self.u(x);
        }
    }
    pub(crate) fn s(&mut self, s: &str) {
        self.u(s.len() as u64);
        self.0.extend_from_slice(s.as_bytes());
    }
}

/// The error of a malformed checkpoint at byte `at`.
pub(crate) fn bad(at: usize, what: &'static str) -> Error {
    Error::InvalidParameter {
        name: "checkpoint",
        value: at as f64,
        allowed: what,
    }
}

/// Reads checkpoint words from bytes, from position `i`.
pub(crate) struct Reader<'a> {
    pub(crate) b: &'a [u8],
    pub(crate) i: usize,
}

impl Reader<'_> {
    pub(crate) fn take(&mut self, k: usize) -> Result<&[u8]> {
        if k > self.b.len() - self.i {
            return Err(bad(self.i, "a complete checkpoint (the bytes end early)"));
        }
        let s = &self.b[self.i..self.i + k];
        self.i += k;
        Ok(s)
    }
    fn word(&mut self) -> Result<[u8; 8]> {
        let mut w = [0u8; 8];
        w.copy_from_slice(self.take(8)?);
        Ok(w)
    }
    pub(crate) fn f(&mut self) -> Result<f64> {
        Ok(f64::from_le_bytes(self.word()?))
    }
    pub(crate) fn u(&mut self) -> Result<u64> {
        Ok(u64::from_le_bytes(self.word()?))
    }
    pub(crate) fn z(&mut self) -> Result<usize> {
        let x = self.u()?;
        if x == u64::MAX {
            return Ok(usize::MAX);
        }
        usize::try_from(x).map_err(|_| bad(self.i, "a checkpoint of this platform"))
    }
    pub(crate) fn b(&mut self) -> Result<bool> {
        match self.u()? {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(bad(self.i, "a well-formed checkpoint (bad flag)")),
        }
    }
    pub(crate) fn dir(&mut self) -> Result<i8> {
        match self.u()? as i64 {
            1 => Ok(1),
            -1 => Ok(-1),
            _ => Err(bad(self.i, "a well-formed checkpoint (direction +1 or -1)")),
        }
    }
    /// A count of items of at least `item` bytes each that the remaining bytes can hold.
    pub(crate) fn len(&mut self, item: usize) -> Result<usize> {
        let k = self.z()?;
        if k == usize::MAX || k.saturating_mul(item.max(1)) > self.b.len() - self.i {
            return Err(bad(self.i, "a well-formed checkpoint (bad length)"));
        }
        Ok(k)
    }
    pub(crate) fn fs(&mut self) -> Result<Vec<f64>> {
        let k = self.len(8)?;
        (0..k).map(|_| self.f()).collect()
    }
    pub(crate) fn zs(&mut self) -> Result<Vec<usize>> {
        let k = self.len(8)?;
        (0..k).map(|_| self.z()).collect()
    }
    pub(crate) fn us(&mut self) -> Result<Vec<u64>> {
        let k = self.len(8)?;
        (0..k).map(|_| self.u()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_malformed_input() {
        let mut w = Writer(Vec::new());
        w.f(-0.1);
        w.z(usize::MAX);
        w.zs(&[3, 5]);
        w.b(true);
        w.i(-1);
        w.us(&[7]);
        let mut r = Reader { b: &w.0, i: 0 };
        assert_eq!(r.f().unwrap().to_bits(), (-0.1f64).to_bits());
        assert_eq!(r.z().unwrap(), usize::MAX);
        assert_eq!(r.zs().unwrap(), vec![3, 5]);
        assert!(r.b().unwrap());
        assert_eq!(r.dir().unwrap(), -1);
        assert_eq!(r.us().unwrap(), vec![7]);
        assert!(r.u().is_err()); // nothing left
        let mut huge = Writer(Vec::new());
        huge.u(1 << 40); // a length no input can hold
        assert!(Reader { b: &huge.0, i: 0 }.fs().is_err());
    }
}
