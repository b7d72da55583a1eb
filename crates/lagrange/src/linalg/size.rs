//! The number of coordinates as a type, so that the assembly loops of small mechanisms are
//! compiled for their exact size (unrolled, without loop set-up), with one dynamic fallback.

/// A number of coordinates known at compile time ([`Fixed`]) or at run time ([`Dynamic`]).
pub(crate) trait Size: Copy {
    /// The number.
    fn get(self) -> usize;
}

/// `N` coordinates, known at compile time.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fixed<const N: usize>;

impl<const N: usize> Size for Fixed<N> {
    #[inline(always)]
    fn get(self) -> usize {
        N
    }
}

/// Any number of coordinates.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Dynamic(pub usize);

impl Size for Dynamic {
    #[inline(always)]
    fn get(self) -> usize {
        self.0
    }
}

/// Call `$body` with `$size` bound to the [`Size`] of `$n`: fixed for 1 to 4, dynamic above.
macro_rules! with_size {
    ($n:expr, $size:ident => $body:expr) => {
        match $n {
            1 => {
                let $size = $crate::linalg::size::Fixed::<1>;
                $body
            }
            2 => {
                let $size = $crate::linalg::size::Fixed::<2>;
                $body
            }
            3 => {
                let $size = $crate::linalg::size::Fixed::<3>;
                $body
            }
            4 => {
                let $size = $crate::linalg::size::Fixed::<4>;
                $body
            }
            n => {
                let $size = $crate::linalg::size::Dynamic(n);
                $body
            }
        }
    };
}
pub(crate) use with_size;
