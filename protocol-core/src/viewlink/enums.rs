//! Enumerations shared by several blocks: servo commands and states, sensors, optical
//! operation commands, tracking commands and tracker states.

code_enum! {
    /// Servo control command (A1 byte 1) and servo status (B1 bits 4..7, values 0..15).
    pub enum ServoCommand: u8 {
        /// 0x00: motor on/off (A1 parameter 1 says which).
        MotorOnOff = 0x00,
        /// 0x01: manual speed mode.
        ManualSpeed = 0x01,
        /// 0x02: follow the current geographic location (not supported yet).
        FollowGeographic = 0x02,
        /// 0x03: follow yaw.
        FollowYaw = 0x03,
        /// 0x04: home position.
        Home = 0x04,
        /// 0x05: azimuth scan (not supported yet).
        AzimuthScan = 0x05,
        /// 0x06: tracking mode.
        Tracking = 0x06,
        /// 0x07: tilt scan (not supported yet).
        TiltScan = 0x07,
        /// 0x08: point to a latitude and longitude (not supported yet).
        PointToTarget = 0x08,
        /// 0x09: manual relative angle mode (current position is 0).
        RelativeAngle = 0x09,
        /// 0x0A: follow yaw disabled.
        FollowYawDisable = 0x0A,
        /// 0x0B: manual absolute angle mode (home position is 0).
        AbsoluteAngle = 0x0B,
        /// 0x0C: follow a space angle (not supported yet).
        FollowSpaceAngle = 0x0C,
        /// 0x0D: manual RC mode.
        ManualRc = 0x0D,
        /// 0x0E: reserved in the command list; 3.3.1.7 gives it as "tracking follow
        /// click/touch".
        TrackClick = 0x0E,
        /// 0x0F: do not change the servo state (parameters meaningless).
        NoChange = 0x0F,
        /// 0x10: manual gyro heading (yaw zero bias) correction.
        GyroCorrection = 0x10,
        /// 0x11: use the frame heading angle servo system only.
        FrameHeadingAngle = 0x11,
        /// 0x12: pitch orthographic (look down 90°).
        LookDown = 0x12,
        /// 0x13: use the frame heading speed servo system only.
        FrameHeadingSpeed = 0x13,
        /// 0x14: use the frame heading angle and speed servo system.
        FrameHeadingAngleSpeed = 0x14,
        /// 0x15: disable the frame heading servo system.
        FrameHeadingDisable = 0x15,
        /// 0x1B: 720° manual absolute angle mode (home position is 0).
        AbsoluteAngle720 = 0x1B,
    }
}

code_enum! {
    /// Image sensor choice of C1 (bits 0..2).
    pub enum Sensor: u8 {
        /// No action.
        NoAction = 0x00,
        /// EO 1 (visible).
        Eo1 = 0x01,
        /// IR thermal.
        Ir = 0x02,
        /// EO 1 main, IR picture-in-picture.
        Eo1IrPip = 0x03,
        /// IR main, EO 1 picture-in-picture.
        IrEo1Pip = 0x04,
        /// Fusion (fixed-lens dual sensor).
        Fusion = 0x05,
        /// IR 1, 13 mm (1352 module).
        Ir1_13mm = 0x06,
        /// IR 2, 52 mm (1352 module).
        Ir2_52mm = 0x07,
    }
}

code_enum! {
    /// Optical operation command of C1 (bits 6..12, 7 bits).
    pub enum OperationCommand: u8 {
        /// No action.
        NoAction = 0x00,
        /// Stop focus, stop zoom.
        StopZoomFocus = 0x01,
        /// Brightness +.
        BrightnessUp = 0x02,
        /// Brightness -.
        BrightnessDown = 0x03,
        /// Contrast + (not supported yet).
        ContrastUp = 0x04,
        /// Contrast - (not supported yet).
        ContrastDown = 0x05,
        /// Aperture + (not supported yet).
        ApertureUp = 0x06,
        /// Aperture - (not supported yet).
        ApertureDown = 0x07,
        /// FOV + (zoom out).
        ZoomOut = 0x08,
        /// FOV - (zoom in).
        ZoomIn = 0x09,
        /// Focus +.
        FocusUp = 0x0A,
        /// Focus -.
        FocusDown = 0x0B,
        /// Internal non-uniformity correction (not supported yet).
        InternalNuc = 0x0C,
        /// External non-uniformity correction (not supported yet).
        ExternalNuc = 0x0D,
        /// IR white hot.
        IrWhiteHot = 0x0E,
        /// IR black hot.
        IrBlackHot = 0x0F,
        /// Gain + (not supported yet).
        GainUp = 0x10,
        /// Gain - (not supported yet).
        GainDown = 0x11,
        /// IR rainbow (pseudo colour).
        IrRainbow = 0x12,
        /// Take a picture.
        TakePicture = 0x13,
        /// Start recording.
        StartRecord = 0x14,
        /// Stop recording.
        StopRecord = 0x15,
        /// Switch to picture mode.
        PictureMode = 0x16,
        /// Switch to record mode.
        RecordMode = 0x17,
        /// Toggle picture / record mode.
        TogglePictureRecord = 0x18,
        /// Auto focus mode.
        AutoFocus = 0x19,
        /// Manual focus mode.
        ManualFocus = 0x1A,
        /// IR digital zoom +.
        IrDzoomIn = 0x1B,
        /// IR digital zoom -.
        IrDzoomOut = 0x1C,
        /// Format the SD card.
        FormatSd = 0x1D,
        /// Query SD card status (T/A series).
        QuerySdStatus = 0x1E,
        /// Query SD card total capacity (T/A series).
        QuerySdTotal = 0x1F,
        /// Query SD card free capacity (T/A series).
        QuerySdFree = 0x20,
        /// IR colour ext 1.
        IrColorExt1 = 0x21,
        /// IR colour ext 2.
        IrColorExt2 = 0x22,
        /// IR colour ext 3.
        IrColorExt3 = 0x23,
        /// IR colour ext 4.
        IrColorExt4 = 0x24,
        /// IR colour ext 5.
        IrColorExt5 = 0x25,
        /// IR colour ext 6.
        IrColorExt6 = 0x26,
        /// Thermal RAW picture (temperature-measuring gimbals only).
        IrRawPicture = 0x33,
        /// Thermal RAW recording start (not supported yet).
        IrRawRecordStart = 0x34,
        /// Thermal RAW recording stop (not supported yet).
        IrRawRecordStop = 0x55,
    }
}

code_enum! {
    /// Laser rangefinder command of C1 (bits 13..15).
    pub enum LrfCommand: u8 {
        /// No action.
        NoAction = 0x00,
        /// Single ranging.
        Single = 0x01,
        /// Continuous ranging start.
        Continuous = 0x02,
        /// LPCL continuous ranging start (pro models).
        LpclContinuous = 0x03,
        /// External sync ranging (not supported yet).
        ExternalSync = 0x04,
        /// Stop ranging.
        Stop = 0x05,
    }
}

code_enum! {
    /// Current video stream of D1 (bits 0..2). Note: one less than the [`Sensor`] code
    /// of C1 for the same stream.
    pub enum VideoSource: u8 {
        /// EO 1 only.
        Eo1 = 0x00,
        /// IR only.
        Ir = 0x01,
        /// EO 1 main, IR picture-in-picture.
        Eo1IrPip = 0x02,
        /// IR main, EO 1 picture-in-picture.
        IrEo1Pip = 0x03,
        Fusion = 0x04,
        /// IR 1 (1352 models).
        Ir1 = 0x05,
        /// IR 2 (1352 models).
        Ir2 = 0x06,
    }
}

code_enum! {
    /// Tracking source of E1 (bits 0..2).
    pub enum TrackingSource: u8 {
        /// No action.
        NoAction = 0x00,
        /// EO 1.
        Eo1 = 0x01,
        Ir = 0x02,
        /// EO 2.
        Eo2 = 0x03,
    }
}

code_enum! {
    /// Basic tracking command of E1 (byte 2).
    pub enum TrackingCommand: u8 {
        /// No action.
        NoAction = 0x00,
        Stop = 0x01,
        /// Search (bring up the cross); parameters 1 and 2 move it.
        Search = 0x02,
        /// Turn on tracking.
        Start = 0x03,
        /// Switch the tracking point to the cross (replaced by start tracking).
        ToCross = 0x04,
        /// AI detection on/off (parameter 2: 0 off, 1 on).
        AiDetection = 0x05,
        /// Reserved in the command list; 3.11.1.4 gives it as "adjust tracking
        /// velocity" (parameter 2, 0.2°/s).
        TrackingSpeed = 0x06,
        /// Reserved in the command list; 3.11.1.3 gives it as "adjust tracking velocity
        /// coefficient" (parameter 2, 0.1).
        SpeedCoefficient = 0x07,
        /// AI: track a target automatically once identified.
        AiAutoTrack = 0x08,
        /// AI: change target when an identified target is clicked.
        AiClickChange = 0x09,
        /// AI: keep the target when an identified target is clicked.
        AiClickKeep = 0x0A,
        /// 16 x 16 ultra small template (reserved).
        Template16 = 0x20,
        /// 32 x 32 small template.
        Template32 = 0x21,
        /// 64 x 64 medium template.
        Template64 = 0x22,
        /// 128 x 128 big template.
        Template128 = 0x23,
        /// Adaptive small / medium template.
        TemplateSmallMedium = 0x24,
        /// Adaptive small / big template.
        TemplateSmallBig = 0x25,
        /// Adaptive medium / big template.
        TemplateMediumBig = 0x26,
        /// Adaptive small / medium / big template.
        TemplateAdaptive = 0x28,
    }
}

code_enum! {
    /// Tracking sensor of F1 (bits 0..2).
    pub enum TrackerSensor: u8 {
        /// EO 1.
        Eo1 = 0x00,
        /// IR thermal camera.
        Ir = 0x01,
        /// EO 2.
        Eo2 = 0x02,
    }
}

code_enum! {
    /// Tracker state of F1 (bits 3..4).
    pub enum TrackerState: u8 {
        Stop = 0x00,
        Search = 0x01,
        Tracking = 0x02,
        /// Target lost.
        Lost = 0x03,
    }
}

code_enum! {
    /// A generic off/on switch (0 / 1).
    pub enum OnOff: u8 {
        /// 0: off / disabled.
        Off = 0,
        /// 1: on / enabled.
        On = 1,
    }
}
