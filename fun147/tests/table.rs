//! The step table: its text form and its register image (FUN147 SR format, derived command
//! table, error-code table). One test per row of the manual's tables.

use fun147::{AsmErrorKind, ErrorCode, MemPlc, Plc, Program, Reg, assemble, disassemble};

/// The seed's example program (FUN147 program example), as the manual prints it: full-width
/// `；` comments in Chinese.
const SEED: &str = "\
001 SPD 5000          ；線速度為 5KHz
 LIN ADR,500,400,300,200,Ut    ；輸出 500(Ps0)/400(Ps1)/300(Ps2)/200(Ps3)個單位
 WAIT TIME,100          ；等待 1 秒
 GOTO NEXT          ；執行下一步
002 SPD R1000          ；線速度存放在 DR1000（R1001 與 R1000）
 LIN ADR,D100,D200, , ,Ut      ；Ps0 行程存放在 DD100，Ps1 行程存放在 DD200
 WAIT TIME,R500          ；等待時間存放在 R500
 GOTO NEXT          ；執行下一步
003 SPD R1002          ；線速度存放在 DR1002（R1003 與 R1002）
 LIN ADR,0,0,R300,R400,Ps        ；Ps2 行程存放在 DR300，Ps3 行程存放在 DR400
 WAIT X0          ；等待 X0 ON 時
 GOTO 1                       ；執行第一步
";

/// The seed's program in words, by the encoding of `fun147::image`.
#[rustfmt::skip]
const SEED_WORDS: [u16; 47] = [
    0xA55C, 3,
    // 001: SPD 5000, LIN ADR 500,400,300,200 Ut, WAIT TIME,100, GOTO NEXT
    0x930F, 0x5501, 0x1388, 0, 0x01F4, 0, 0x0190, 0, 0x012C, 0, 0x00C8, 0, 0x0001, 0x0064, 0,
    // 002: SPD R1000, LIN ADR D100,D200,_,_ Ut, WAIT TIME,R500, GOTO NEXT
    0x930F, 0x0F11, 1000, 0, 100, 0, 200, 0, 0, 0, 0, 0, 0x0011, 500, 0,
    // 003: SPD R1002, LIN ADR 0,0,R300,R400 Ps, WAIT X0, GOTO 1
    0x930F, 0xA519, 1002, 0, 0, 0, 0, 0, 300, 0, 400, 0, 0x0102, 0, 1,
];

/// FUN147 SR format: N = 3 takes 3×15+2 = 47 registers; step 2 at SR+17, step 3 at SR+32.
#[test]
fn three_steps_take_47_registers() {
    let program = assemble(SEED).unwrap();
    let words = program.to_words();
    assert_eq!(words.len(), 47);
    assert_eq!((words[0], words[1]), (0xA55C, 3));
    assert_eq!((words[2], words[17], words[32]), (0x930F, 0x930F, 0x930F));
    let mut plc = MemPlc::new();
    plc.set_word(Reg::R(147), 0x1234);
    program.write(&mut plc, Reg::R(100)).unwrap();
    assert_eq!(plc.word(Reg::R(146)), 1, "SR+46 is step 3's last word (GOTO 1)");
    assert_eq!(plc.word(Reg::R(147)), 0x1234, "SR+47 is not the table's");
    assert_eq!(Program::read(&plc, Reg::R(100)).unwrap(), program);
}

/// The encoding, word for word, of the manual's example; and back.
#[test]
fn seed_program_words() {
    let program = assemble(SEED).unwrap();
    assert_eq!(program.to_words(), SEED_WORDS);
    assert_eq!(Program::from_words(&SEED_WORDS).unwrap(), program);
    let text = disassemble(&program);
    assert_eq!(assemble(&text).unwrap(), program, "{text}");
    assert!(
        text.starts_with("001 SPD 5000\n    LIN ADR,500,400,300,200,Ut\n    WAIT TIME,100\n    GOTO NEXT\n"),
        "{text}"
    );
    assert!(text.contains("    LIN ADR,D100,D200,,,Ut\n    WAIT TIME,R500\n"), "{text}");
}

fn seed_with(index: usize, value: u16) -> Vec<u16> {
    let mut words = SEED_WORDS.to_vec();
    words[index] = value;
    words
}

fn code_of(words: &[u16]) -> Option<u16> {
    Program::from_words(words).err().map(ErrorCode::code)
}

/// FUN147 error-code table: what decoding an image reports, one row per code.
#[test]
fn decoding_checks() {
    let (step1, step3) = (2, 32);
    let mut short = SEED_WORDS.to_vec();
    short.pop();
    let rows: Vec<(&str, Vec<u16>, Option<u16>)> = vec![
        ("the example", SEED_WORDS.to_vec(), None),
        ("SR+0 0xA55B", seed_with(0, 0xA55B), Some(34)),
        ("SR+0 0", seed_with(0, 0), Some(34)),
        ("N = 0", seed_with(1, 0), Some(36)),
        ("N = 256", seed_with(1, 256), Some(36)),
        ("N = 4, 3 steps stored", seed_with(1, 4), Some(35)),
        ("46 words", short, Some(35)),
        ("step header 0x930E", seed_with(step3, 0x930E), Some(35)),
        ("mode 0", seed_with(step1 + 1, 0x5500), Some(60)),
        ("mode 3", seed_with(step1 + 1, 0x5503), Some(60)),
        ("reserved command bit", seed_with(step1 + 1, 0x5541), Some(60)),
        ("SPD operand kind 3", seed_with(step1 + 1, 0x5531), Some(30)),
        ("SPD R3839 (no R3840)", seed_with(17 + 2, 3839), Some(30)),
        ("SPD R4000", seed_with(17 + 2, 4000), Some(30)),
        ("SPD register, high word set", seed_with(17 + 3, 1), Some(30)),
        ("SPD 0", seed_with(step1 + 2, 0), Some(31)),
        ("blank travel with words", seed_with(17 + 8, 5), Some(60)),
        ("travel D4000", seed_with(17 + 4, 4000), Some(32)),
        ("GOTO 4 of 3", seed_with(step3 + 14, 4), Some(36)),
        ("GOTO 0", seed_with(step3 + 14, 0), Some(36)),
        ("condition 10", seed_with(step3 + 12, 0x010A), Some(60)),
        ("GOTO NEXT with an operand", seed_with(step1 + 14, 3), Some(60)),
    ];
    for (name, words, code) in rows {
        assert_eq!(code_of(&words), code, "{name}");
    }
    let mut m1912 = seed_with(step3 + 12, 0x0104);
    m1912[step3 + 13] = 1912;
    assert_eq!(code_of(&m1912), Some(60), "WAIT M1912: M above M1911");
    m1912[step3 + 13] = 1911;
    assert_eq!(code_of(&m1912), None, "WAIT M1911");
}

fn speed_words(speed: i32) -> Vec<u16> {
    let mut words = seed_with(4, speed as u16);
    words[5] = (speed >> 16) as u16;
    words
}

fn travel_words(travel: i32) -> Vec<u16> {
    let mut words = seed_with(6, travel as u16);
    words[7] = (travel >> 16) as u16;
    words
}

/// FUN147 SPD table: 1 ≤ SPD ≤ 1,840,000, else 31; LIN table: ±1,999,999 Ps a move, else 40.
#[test]
fn constant_ranges() {
    for (speed, code) in [(0, Some(31)), (1, None), (1_840_000, None), (1_840_001, Some(31)), (-5, Some(31))] {
        assert_eq!(code_of(&speed_words(speed)), code, "SPD {speed}");
    }
    for (travel, code) in [(1_999_999, None), (-1_999_999, None), (2_000_000, Some(40)), (-2_000_000, Some(40))] {
        assert_eq!(code_of(&travel_words(travel)), code, "travel {travel}");
    }
}

fn asm_error(text: &str) -> (usize, usize, AsmErrorKind) {
    let e = assemble(text).unwrap_err();
    (e.line, e.column, e.kind)
}

/// The text form: what the assembler refuses, and where.
#[test]
fn assembler_errors() {
    let head = "001 SPD 5000\n";
    let count = |command, expected| AsmErrorKind::OperandCount { command, expected };
    assert_eq!(
        asm_error(&format!("{head}    LIN ADR,500,400,300,Ut")),
        (2, 5, count("LIN", "six operands: ADR|ABS, X, Y, Z, W, Ut|Ps"))
    );
    assert_eq!(asm_error(&format!("{head}  FOO 1")), (2, 3, AsmErrorKind::UnknownCommand("FOO".into())));
    assert_eq!(asm_error("001 SPD 0\n LIN ADR,1,,,,Ps"), (1, 9, AsmErrorKind::Value(ErrorCode::SpeedValue)));
    assert_eq!(asm_error("001 SPD 1840001\n LIN ADR,1,,,,Ps").2, AsmErrorKind::Value(ErrorCode::SpeedValue));
    assert_eq!(
        asm_error(&format!("{head} LIN ADR, 2000000,,,,Ps")),
        (2, 11, AsmErrorKind::Value(ErrorCode::TravelRange))
    );
    assert_eq!(asm_error("002 SPD 1").2, AsmErrorKind::StepNumber { expected: 1, found: "002".into() });
    assert_eq!(asm_error(" SPD 1"), (1, 2, AsmErrorKind::NoStep));
    assert_eq!(asm_error(&format!("{head} LIN ADR,1,,,,Ps\n WAIT M1912")).0, 3);
    assert_eq!(
        asm_error(&format!("{head} LIN ADR,1,,,,Ps\n WAIT X0\n EXT X1")),
        (4, 2, AsmErrorKind::Twice("WAIT/EXT"))
    );
    assert_eq!(
        asm_error(&format!("{head} LIN ADR,1,,,,Ps\n GOTO 2")),
        (3, 7, AsmErrorKind::Value(ErrorCode::StepCount))
    );
    assert_eq!(asm_error(&format!("{head} LIN ADR,1,,,,Ps\n MEND\n GOTO 1")).2, AsmErrorKind::AfterMend);
    assert_eq!(
        asm_error(&format!("{head} WAIT X0\n002 SPD 1")),
        (3, 1, AsmErrorKind::Missing { step: 1, missing: "LIN/LINE" })
    );
    assert_eq!(asm_error("; nothing\n").2, AsmErrorKind::Empty);
    assert_eq!(asm_error(&format!("{head} LIN ADR,R3839,,,,Ps")).1, 10, "R3839 has no high word");
    assert_eq!(asm_error(&format!("{head} LIN ADR,1,,,,mm")).1, 15);
}

/// Case does not matter; `−`, `，` and `；` are the manual's characters; GOTO Dn and EXT.
#[test]
fn assembler_forms() {
    let program = assemble("001 spd d10\n lin abs,−10000，,,,ps ； comment\n ext s999\n goto d10\n mend\n").unwrap();
    let words = program.to_words();
    assert_eq!(&words[2..], &[0x930F, 0x012D, 10, 0, 0xD8F0, 0xFFFF, 0, 0, 0, 0, 0, 0, 0x0309, 999, 10]);
    let program = assemble("001 SPD 1\n LINE ADR,1000,500,300,0,Ps\n WAIT TIME, 65535\n").unwrap();
    assert_eq!(&program.to_words()[2..4], &[0x930F, 0x550A]);
    assert!(assemble("001 SPD 1\n LIN ADR,1,,,,Ps\n WAIT TIME,65536\n").is_err());
}

/// What a user reads: where, and the manual's code.
#[test]
fn error_messages() {
    let e = assemble("001 SPD 0\n LIN ADR,1,,,,Ps").unwrap_err();
    assert_eq!(e.to_string(), "line 1, column 9: FUN147 error 31: speed setting value error");
    let e = assemble("001 SPD 1\n LIN ADR,1,,,Ps").unwrap_err();
    assert_eq!(e.to_string(), "line 2, column 2: LIN takes six operands: ADR|ABS, X, Y, Z, W, Ut|Ps");
}
