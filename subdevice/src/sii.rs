//! The slave information interface: the EEPROM image an ESC carries (ETG.1000.6 table 16
//! and ETG.2010 table 2: the configuration area with its checksum, the identity, the
//! mailbox defaults; then the categories of ETG.1000.6 table 19: strings, general, FMMU,
//! SyncManager, TxPDO and RxPDO, ETG.2010 table 14), and the protocol a master reads and
//! writes it through (ETG.1000.4 table 48, registers 0x0500-0x050F).

use devices::coe::DataType;

use crate::registers::{PDI_CONTROL, Registers, SII_ADDRESS, SII_CONFIG, SII_CONTROL, SII_DATA, STATION_ALIAS};

/// Word address of the first category (ETG.2010 table 2).
pub const FIRST_CATEGORY: usize = 0x40;
/// Category types (ETG.1000.6 table 19).
pub const CATEGORY_STRINGS: u16 = 10;
/// General information.
pub const CATEGORY_GENERAL: u16 = 30;
/// FMMU usage.
pub const CATEGORY_FMMU: u16 = 40;
/// SyncManagers.
pub const CATEGORY_SYNC_MANAGER: u16 = 41;
/// TxPDOs (inputs).
pub const CATEGORY_TXPDO: u16 = 50;
/// RxPDOs (outputs).
pub const CATEGORY_RXPDO: u16 = 51;
/// End of the categories.
pub const CATEGORY_END: u16 = 0xFFFF;

/// Word addresses of the fixed fields (ETG.2010 table 2).
pub const WORD_PDI_CONTROL: usize = 0x00;
/// Configured station alias.
pub const WORD_ALIAS: usize = 0x04;
/// CRC of words 0-6.
pub const WORD_CHECKSUM: usize = 0x07;
/// Vendor ID (32 bits).
pub const WORD_VENDOR: usize = 0x08;
/// Product code.
pub const WORD_PRODUCT: usize = 0x0A;
/// Revision number.
pub const WORD_REVISION: usize = 0x0C;
/// Serial number.
pub const WORD_SERIAL: usize = 0x0E;
/// Standard receive mailbox offset, size, send mailbox offset, size.
pub const WORD_MAILBOX: usize = 0x18;
/// Mailbox protocols.
pub const WORD_PROTOCOLS: usize = 0x1C;
/// EEPROM size in kbit, minus 1.
pub const WORD_SIZE: usize = 0x3E;
/// Version of the layout.
pub const WORD_VERSION: usize = 0x3F;

/// Mailbox protocol bit of CoE (ETG.2010 table 2, word 0x1C).
pub const PROTOCOL_COE: u16 = 0x0004;
/// General category CoE details (ETG.2010 table 7): SDO, PDO assignment, PDO configuration.
pub const COE_DETAILS: u8 = 0x01 | 0x04 | 0x08;
/// PDI control word: an SPI slave interface (the simulated application's side; a master
/// only reads it).
const PDI_SPI: u16 = 0x0005;

/// SII control/status bits (ETG.1000.4 table 48).
const WRITE_ENABLE: u16 = 1 << 0;
/// The interface reads 8 bytes per read command.
const READ_8_BYTES: u16 = 1 << 6;
const COMMAND_MASK: u16 = 0b111 << 8;
const COMMAND_READ: u16 = 0b001 << 8;
const COMMAND_WRITE: u16 = 0b010 << 8;
const COMMAND_RELOAD: u16 = 0b100 << 8;
/// Missing acknowledge or invalid command.
const ERROR_COMMAND: u16 = 1 << 13;
/// A write without write enable.
const ERROR_WRITE_ENABLE: u16 = 1 << 14;
/// SII config bit 0: the EEPROM is offered to the PDI, and EtherCAT has no access.
const OFFERED_TO_PDI: u8 = 1;

/// Identity of a device, as its object 0x1018 states it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Identity {
    /// 0x1018:01.
    pub vendor: u32,
    /// 0x1018:02.
    pub product: u32,
    /// 0x1018:03.
    pub revision: u32,
    /// 0x1018:04.
    pub serial: u32,
}

/// A SyncManager as the SII describes it (ETG.2010 table 12).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SmDescription {
    /// Physical start.
    pub start: u16,
    /// Default length.
    pub length: u16,
    /// Control register value.
    pub control: u8,
    /// Enabled by default.
    pub enable: bool,
    /// 1 mailbox out, 2 mailbox in, 3 outputs, 4 inputs.
    pub kind: u8,
}

/// One mapped object of a PDO as the SII describes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PdoEntryDescription {
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// Its type.
    pub ty: DataType,
}

/// A PDO as the SII describes it (ETG.2010 table 14).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PdoDescription {
    /// The mapping object (0x1600.., 0x1A00..).
    pub index: u16,
    /// The SyncManager that carries it.
    pub sync_manager: u8,
    /// Its entries in order.
    pub entries: Vec<PdoEntryDescription>,
}

/// What the EEPROM image is made of.
#[derive(Clone, Debug)]
pub struct SiiContents {
    /// From the device's 0x1018.
    pub identity: Identity,
    /// Device name (string 1).
    pub name: String,
    /// SM0 to SM3.
    pub sync_managers: [SmDescription; 4],
    /// RxPDOs assigned by default.
    pub rx_pdos: Vec<PdoDescription>,
    /// TxPDOs assigned by default.
    pub tx_pdos: Vec<PdoDescription>,
}

/// The base data type index of ETG.1000.6 table 64.
pub fn data_type_index(ty: DataType) -> u8 {
    match ty {
        DataType::Int8 => 0x02,
        DataType::Int16 => 0x03,
        DataType::Int32 => 0x04,
        DataType::UInt8 => 0x05,
        DataType::UInt16 => 0x06,
        DataType::UInt32 => 0x07,
        DataType::Real32 => 0x08,
    }
}

/// The CRC-8 of the configuration area (ETG.2010: polynomial x^8 + x^2 + x + 1, initial
/// value 0xFF, over bytes 0-13).
pub fn checksum(bytes: &[u8]) -> u8 {
    let mut crc = 0xFFu8;
    for &byte in bytes {
        crc ^= byte;
        for _ in 0..8 {
            crc = if crc & 0x80 != 0 { (crc << 1) ^ 0x07 } else { crc << 1 };
        }
    }
    crc
}

/// The EEPROM, as 16-bit words.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Eeprom {
    words: Vec<u16>,
}

/// Bytes as little-endian words, the last padded with 0.
fn words_of(bytes: &[u8]) -> impl Iterator<Item = u16> + '_ {
    bytes.chunks(2).map(|pair| u16::from_le_bytes([pair[0], pair.get(1).copied().unwrap_or(0)]))
}

impl Eeprom {
    /// The image of a device.
    pub fn build(contents: &SiiContents) -> Self {
        let mut words = vec![0u16; FIRST_CATEGORY];
        words[WORD_PDI_CONTROL] = PDI_SPI;
        let crc_bytes: Vec<u8> = words[..WORD_CHECKSUM].iter().flat_map(|w| w.to_le_bytes()).collect();
        words[WORD_CHECKSUM] = u16::from(checksum(&crc_bytes));
        let identity = contents.identity;
        for (at, value) in [
            (WORD_VENDOR, identity.vendor),
            (WORD_PRODUCT, identity.product),
            (WORD_REVISION, identity.revision),
            (WORD_SERIAL, identity.serial),
        ] {
            words[at] = value as u16;
            words[at + 1] = (value >> 16) as u16;
        }
        let [rx, tx, ..] = contents.sync_managers;
        words[WORD_MAILBOX..WORD_MAILBOX + 4].copy_from_slice(&[rx.start, rx.length, tx.start, tx.length]);
        words[WORD_PROTOCOLS] = PROTOCOL_COE;
        words[WORD_VERSION] = 1;

        let name = contents.name.as_bytes();
        let name = &name[..name.len().min(255)];
        let mut strings = vec![1, name.len() as u8];
        strings.extend_from_slice(name);
        let mut general = [0u8; 32];
        // ETG.2010 table 6: OrderIdx and NameIdx both string 1 (SOEM names a slave by
        // the name, ethercrab by the order number).
        general[2] = 1;
        general[3] = 1;
        general[5] = COE_DETAILS;
        let fmmu = [0x01, 0x02];
        let sms: Vec<u8> = contents
            .sync_managers
            .iter()
            .flat_map(|sm| {
                let [s0, s1] = sm.start.to_le_bytes();
                let [l0, l1] = sm.length.to_le_bytes();
                [s0, s1, l0, l1, sm.control, 0, u8::from(sm.enable), sm.kind]
            })
            .collect();
        for (kind, data) in [
            (CATEGORY_STRINGS, strings),
            (CATEGORY_GENERAL, general.to_vec()),
            (CATEGORY_FMMU, fmmu.to_vec()),
            (CATEGORY_SYNC_MANAGER, sms),
            (CATEGORY_TXPDO, pdo_category(&contents.tx_pdos)),
            (CATEGORY_RXPDO, pdo_category(&contents.rx_pdos)),
        ] {
            words.push(kind);
            words.push(data.len().div_ceil(2) as u16);
            words.extend(words_of(&data));
        }
        words.push(CATEGORY_END);
        // The smallest EEPROM of 2^n kbit that holds the image.
        let kbit = (words.len() * 16).div_ceil(1024).next_power_of_two();
        words[WORD_SIZE] = kbit as u16 - 1;
        Eeprom { words }
    }

    /// One word; an address past the image reads as erased EEPROM (0xFFFF).
    pub fn word(&self, address: u32) -> u16 {
        usize::try_from(address).ok().and_then(|a| self.words.get(a)).copied().unwrap_or(0xFFFF)
    }

    /// Writes one word inside the EEPROM's size; returns whether it was there.
    pub fn write_word(&mut self, address: u32, value: u16) -> bool {
        let size_words = (usize::from(self.words[WORD_SIZE]) + 1) * 1024 / 16;
        match usize::try_from(address) {
            Ok(a) if a < size_words => {
                if a >= self.words.len() {
                    self.words.resize(a + 1, 0xFFFF);
                }
                self.words[a] = value;
                true
            }
            _ => false,
        }
    }
}

/// A TxPDO or RxPDO category: per PDO its header, then 8 bytes per entry.
fn pdo_category(pdos: &[PdoDescription]) -> Vec<u8> {
    let mut data = Vec::new();
    for pdo in pdos {
        let [i0, i1] = pdo.index.to_le_bytes();
        data.extend_from_slice(&[i0, i1, pdo.entries.len() as u8, pdo.sync_manager, 0, 0, 0, 0]);
        for entry in &pdo.entries {
            let [e0, e1] = entry.index.to_le_bytes();
            data.extend_from_slice(&[e0, e1, entry.sub, 0, data_type_index(entry.ty), entry.ty.bits(), 0, 0]);
        }
    }
    data
}

/// The SII interface of one ESC: the EEPROM behind registers 0x0500-0x050F.
#[derive(Clone, Debug)]
pub struct SiiInterface {
    eeprom: Eeprom,
}

impl SiiInterface {
    /// The interface over an EEPROM, with the registers it loads at power-up (the PDI
    /// control and the alias) and its status.
    pub fn new(eeprom: Eeprom, registers: &mut Registers) -> Self {
        let sii = SiiInterface { eeprom };
        sii.reload(registers);
        registers.set_u16(SII_CONTROL, READ_8_BYTES);
        sii
    }

    /// The image.
    pub fn eeprom(&self) -> &Eeprom {
        &self.eeprom
    }

    fn reload(&self, registers: &mut Registers) {
        registers.set_u16(PDI_CONTROL, self.eeprom.word(WORD_PDI_CONTROL as u32));
        registers.set_u16(STATION_ALIAS, self.eeprom.word(WORD_ALIAS as u32));
    }

    /// The master wrote `control` into 0x0502: the command is carried out at once (the
    /// busy bit is never seen set). A command while the EEPROM is offered to the PDI is
    /// ignored; no command (0) clears the error bits.
    pub fn control_written(&mut self, registers: &mut Registers, control: u16) {
        if registers.byte(SII_CONFIG) & OFFERED_TO_PDI != 0 {
            return;
        }
        let address = registers.u32(SII_ADDRESS);
        let error = match control & COMMAND_MASK {
            0 => 0,
            COMMAND_READ => {
                for i in 0..4u32 {
                    registers.set_u16(SII_DATA + 2 * i as u16, self.eeprom.word(address.wrapping_add(i)));
                }
                0
            }
            COMMAND_WRITE if control & WRITE_ENABLE == 0 => ERROR_WRITE_ENABLE,
            COMMAND_WRITE if self.eeprom.write_word(address, registers.u16(SII_DATA)) => 0,
            COMMAND_RELOAD => {
                self.reload(registers);
                0
            }
            _ => ERROR_COMMAND,
        };
        registers.set_u16(SII_CONTROL, READ_8_BYTES | error);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contents() -> SiiContents {
        let sm = |start, length, control, kind| SmDescription { start, length, control, enable: true, kind };
        let entry = |index, sub, ty| PdoEntryDescription { index, sub, ty };
        SiiContents {
            identity: Identity { vendor: 0xAAAA, product: 2, revision: 1, serial: 0 },
            name: "HIWIN D1".into(),
            sync_managers: [
                sm(0x1800, 246, 0x26, 1),
                sm(0x18F6, 246, 0x22, 2),
                sm(0x1000, 6, 0x64, 3),
                sm(0x1100, 2, 0x20, 4),
            ],
            rx_pdos: vec![PdoDescription {
                index: 0x1600,
                sync_manager: 2,
                entries: vec![entry(0x6040, 0, DataType::UInt16), entry(0x607A, 0, DataType::Int32)],
            }],
            tx_pdos: vec![PdoDescription {
                index: 0x1A00,
                sync_manager: 3,
                entries: vec![entry(0x6041, 0, DataType::UInt16)],
            }],
        }
    }

    /// The CRC's check value (its catalogue's input "123456789"), and the image's own.
    #[test]
    fn the_checksum_is_etg_2010_s_crc_8() {
        assert_eq!(checksum(&[]), 0xFF);
        assert_eq!(checksum(b"123456789"), 0xFB);
        let mut area = [0u8; 14];
        area[0] = PDI_SPI as u8;
        assert_eq!(Eeprom::build(&contents()).word(WORD_CHECKSUM as u32), u16::from(checksum(&area)));
    }

    #[test]
    fn the_image_holds_identity_mailbox_and_categories() {
        let eeprom = Eeprom::build(&contents());
        let word = |a: usize| eeprom.word(a as u32);
        assert_eq!((word(WORD_VENDOR), word(WORD_VENDOR + 1)), (0xAAAA, 0));
        assert_eq!(word(WORD_PRODUCT), 2);
        assert_eq!(word(WORD_REVISION), 1);
        assert_eq!([word(0x18), word(0x19), word(0x1A), word(0x1B)], [0x1800, 246, 0x18F6, 246]);
        assert_eq!(word(WORD_PROTOCOLS), PROTOCOL_COE);
        // Strings: 1 string of 8 bytes, padded: 10 bytes, 5 words.
        assert_eq!([word(0x40), word(0x41), word(0x42)], [CATEGORY_STRINGS, 5, 0x0801]);
        assert_eq!(word(0x43), u16::from_le_bytes(*b"HI"));
        assert_eq!([word(0x47), word(0x48)], [CATEGORY_GENERAL, 16]);
        assert_eq!(word(0x49 + 1), 0x0101, "bytes 2 and 3: OrderIdx and NameIdx, string 1");
        assert_eq!(word(0x49 + 2), u16::from(COE_DETAILS) << 8, "byte 5: CoE details");
        let fmmu = 0x49 + 16;
        assert_eq!([word(fmmu), word(fmmu + 1), word(fmmu + 2)], [CATEGORY_FMMU, 1, 0x0201]);
        let sm = fmmu + 3;
        assert_eq!([word(sm), word(sm + 1), word(sm + 2), word(sm + 3)], [CATEGORY_SYNC_MANAGER, 16, 0x1800, 246]);
        let tx = sm + 2 + 16;
        assert_eq!([word(tx), word(tx + 1), word(tx + 2), word(tx + 3)], [CATEGORY_TXPDO, 8, 0x1A00, 0x0301]);
        assert_eq!([word(tx + 6), word(tx + 7), word(tx + 8)], [0x6041, 0x0000, 0x1006], "UNSIGNED16, 16 bits");
        let rx = tx + 2 + 8;
        assert_eq!([word(rx), word(rx + 1), word(rx + 2), word(rx + 3)], [CATEGORY_RXPDO, 12, 0x1600, 0x0202]);
        assert_eq!(word(rx + 2 + 12), CATEGORY_END);
        assert_eq!(word(0x7FFF), 0xFFFF, "past the image: erased");
        assert_eq!(word(WORD_SIZE), 3, "135 words: 4 kbit");
    }

    /// The read protocol: address, read command, 8 bytes in the data registers.
    #[test]
    fn a_master_reads_and_writes_words_through_the_registers() {
        let mut registers = Registers::default();
        let mut sii = SiiInterface::new(Eeprom::build(&contents()), &mut registers);
        registers.set_u32(SII_ADDRESS, WORD_VENDOR as u32);
        sii.control_written(&mut registers, COMMAND_READ);
        assert_eq!(registers.bytes::<8>(SII_DATA), [0xAA, 0xAA, 0, 0, 2, 0, 0, 0]);
        assert_eq!(registers.u16(SII_CONTROL), READ_8_BYTES);
        registers.set_u32(SII_ADDRESS, 0x60);
        registers.set_u16(SII_DATA, 0xBEEF);
        sii.control_written(&mut registers, COMMAND_WRITE);
        assert_eq!(registers.u16(SII_CONTROL), READ_8_BYTES | ERROR_WRITE_ENABLE);
        sii.control_written(&mut registers, COMMAND_WRITE | WRITE_ENABLE);
        assert_eq!(sii.eeprom().word(0x60), 0xBEEF);
        sii.control_written(&mut registers, 0x0700);
        assert_eq!(registers.u16(SII_CONTROL), READ_8_BYTES | ERROR_COMMAND);
        sii.control_written(&mut registers, 0);
        assert_eq!(registers.u16(SII_CONTROL), READ_8_BYTES, "no command clears the errors");
        registers.set_byte(SII_CONFIG, OFFERED_TO_PDI);
        registers.set_u32(SII_ADDRESS, WORD_PRODUCT as u32);
        sii.control_written(&mut registers, COMMAND_READ);
        assert_eq!(registers.u16(SII_DATA), 0xBEEF, "the PDI has the EEPROM: nothing read");
    }
}
