//! The feedback part of GCU packages: the order answered and its execution state.

use super::{CameraSet, Order};
use crate::wire::Writer;
use crate::{Error, Result};

wire_derive! {
    [Eq, Hash]
    /// How the byte after the order in a GCU feedback part reads.
    pub enum FeedbackKind {
        /// 0x00 success, 0x01 fail, 0x02 operating (calibration).
        Status,
        /// 0x00 success, otherwise the set of cameras that failed (`NN`).
        Cameras,
    }
}

wire_derive! {
    custom_serde [Eq, Hash]
    /// The execution state in a GCU feedback part (the byte after the order).
    ///
    /// Serialised like the crate's enumerations, `{"name": "FailedCameras", "code": 3}`.
    pub enum Execution {
        /// 0x00: success.
        Success,
        /// 0x01 for a [`FeedbackKind::Status`] order: fail.
        Fail,
        /// 0x02 for a [`FeedbackKind::Status`] order: operating (calibration).
        Operating,
        /// Non-zero for a [`FeedbackKind::Cameras`] order: the cameras that failed (`NN`).
        FailedCameras(CameraSet),
        /// Another value for a [`FeedbackKind::Status`] order, kept as received.
        Other(u8),
    }
}

impl Execution {
    /// The execution state for a byte, read as `kind` says.
    #[must_use]
    pub const fn from_value(kind: FeedbackKind, v: u8) -> Execution {
        match (kind, v) {
            (_, 0x00) => Execution::Success,
            (FeedbackKind::Cameras, v) => Execution::FailedCameras(CameraSet(v)),
            (FeedbackKind::Status, 0x01) => Execution::Fail,
            (FeedbackKind::Status, 0x02) => Execution::Operating,
            (FeedbackKind::Status, v) => Execution::Other(v),
        }
    }

    /// The byte on the wire.
    #[must_use]
    pub const fn value(self) -> u8 {
        match self {
            Execution::Success => 0x00,
            Execution::Fail => 0x01,
            Execution::Operating => 0x02,
            Execution::FailedCameras(c) => c.0,
            Execution::Other(v) => v,
        }
    }

    /// The variant's name.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Execution::Success => "Success",
            Execution::Fail => "Fail",
            Execution::Operating => "Operating",
            Execution::FailedCameras(_) => "FailedCameras",
            Execution::Other(_) => "Other",
        }
    }

    /// The failure state to report for `order`: [`Execution::Fail`] for a status order,
    /// the `cameras` the command named for a camera order (or camera 1 if it named
    /// none, so the byte is never the 0x00 of success).
    #[must_use]
    pub const fn failure(order: Order, cameras: CameraSet) -> Execution {
        match order.feedback_kind() {
            FeedbackKind::Status => Execution::Fail,
            FeedbackKind::Cameras if cameras.is_empty() => {
                Execution::FailedCameras(CameraSet::CAMERA_1)
            }
            FeedbackKind::Cameras => Execution::FailedCameras(cameras),
        }
    }

    /// True for success.
    #[must_use]
    pub const fn is_success(self) -> bool {
        self.value() == 0
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for Execution {
    fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
        crate::macros::serialize_code(s, self.name(), self.value())
    }
}

wire_derive! {
    [Eq, Hash]
    /// The feedback part of a GCU package: the order answered and its execution state.
    ///
    /// The document prints every feedback as `order, state`. A feedback with the order
    /// byte alone decodes with `execution: None`; bytes after the state are kept in
    /// `extra`.
    pub struct Feedback<'a> {
        /// The order answered.
        pub order: Order,
        /// Its execution state (`None` when the package ends after the order byte).
        pub execution: Option<Execution>,
        /// Bytes after the execution state, kept as received (none in the document).
        pub extra: &'a [u8],
    }
}

impl<'a> Feedback<'a> {
    /// The feedback `order, execution`.
    #[must_use]
    pub const fn new(order: Order, execution: Execution) -> Self {
        Feedback {
            order,
            execution: Some(execution),
            extra: &[],
        }
    }

    /// Success feedback for `order` (what the GCU answers to a command it accepted).
    #[must_use]
    pub const fn success(order: Order) -> Self {
        Feedback::new(order, Execution::Success)
    }

    /// The feedback for an order byte (the message id) and the payload after it.
    #[must_use]
    pub fn decode(id: u8, payload: &'a [u8]) -> Self {
        let order = Order::from_value(id);
        let (execution, extra) = match payload.split_first() {
            Some((&v, extra)) => (Some(Execution::from_value(order.feedback_kind(), v)), extra),
            None => (None, payload),
        };
        Feedback {
            order,
            execution,
            extra,
        }
    }

    /// The order byte (the message id).
    #[must_use]
    pub const fn id(&self) -> u8 {
        self.order.value()
    }

    /// Length of the payload: the bytes after the order byte.
    #[must_use]
    pub const fn payload_len(&self) -> usize {
        match self.execution {
            Some(_) => self.extra.len().saturating_add(1),
            None => self.extra.len(),
        }
    }

    /// Writes the payload: the execution state and the extra bytes (the order byte is
    /// the frame's id).
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for extra bytes without an execution state (they would
    /// read as one); [`Error::BufferTooSmall`] when `w` has no room.
    pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        match self.execution {
            Some(e) => w.u8(e.value())?,
            None if !self.extra.is_empty() => return Err(Error::OutOfRange),
            None => {}
        }
        w.put(self.extra)
    }
}
